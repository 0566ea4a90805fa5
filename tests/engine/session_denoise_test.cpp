// Session::set_denoise during a run (the live viewer's toggle, issue 52): the method is
// taken up when a frame starts, after the observer's before_frame(); a switch starts every
// lane's history again, so the frame after it is what a new denoiser makes of it, while
// the same method again keeps the history. A frame rendered at a reduced image scale (the
// viewer's moving frames) is filtered at the size it was rendered, then enlarged.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <vector>

#include "balance/balancer.h"
#include "core/resample.h"
#include "device/cpu/cpu_device.h"
#include "engine/frame_advisor.h"
#include "engine/frame_denoiser.h"
#include "engine/half_scale_advisor.h"
#include "engine/session.h"
#include "scene/builders.h"

namespace multiray {
namespace session_denoise_test {

constexpr int kW = 24, kH = 16;

// Asks for the method of `plan` before each frame, and keeps every frame.
struct Switcher : FrameObserver {
  Session* session = nullptr;
  std::map<int, DenoiseMethod> plan;
  std::vector<std::shared_ptr<const FrameResult>> results;
  void before_frame(int frame, const FrameInput&) override { session->set_denoise(plan[frame]); }
  void on_frame(const std::shared_ptr<const FrameResult>& r) override { results.push_back(r); }
};

// What a denoiser with no history makes of frame `r`.
uint64_t fresh_denoised(DenoiseMethod method, const Camera& camera, const FrameResult& r) {
  ViewSetup view;
  view.camera = camera;
  view.width = kW, view.height = kH;
  FrameDenoiser fresh(method);
  std::vector<Framebuffer> out;
  fresh.apply({view}, r.images, out);
  return image_hash(out.at(0));
}

TEST(SessionDenoise, ASwitchBetweenFramesStartsTheHistoryAgain) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice cpu(cache, CpuDeviceOptions{}, "cpu");
  RenderSettings settings{.spp = 1, .max_bounces = 2};
  settings.feature_buffers = true;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  lanes.push_back(balance::make_balancer("uniform", 1));
  Session session({&cpu}, std::move(lanes), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::fixed(scene.cameras[0]), settings);
  Switcher s;
  s.session = &session;
  using M = DenoiseMethod;
  s.plan = {{0, M::svgf}, {1, M::svgf}, {2, M::svgf}, {3, M::atrous}, {4, M::none}, {5, M::svgf}};
  ASSERT_EQ(session.run(0, 6, s), 6);
  ASSERT_EQ(s.results.size(), 6u);
  for (int f = 0; f < 6; ++f) {
    const FrameResult& r = *s.results[size_t(f)];
    EXPECT_EQ(r.denoised_with, s.plan[f]) << "frame " << f;
    EXPECT_EQ(r.denoised.empty(), s.plan[f] == M::none) << "frame " << f;
  }
  const Camera& camera = scene.cameras[0];
  const auto denoised = [&](int f) { return image_hash(s.results[size_t(f)]->denoised.at(0)); };
  // The same method again: svgf's history of frames 0 and 1 is in frame 2.
  EXPECT_NE(denoised(2), fresh_denoised(M::svgf, camera, *s.results[2]));
  // A switch: atrous from scratch; svgf after a frame without a denoiser starts again.
  EXPECT_EQ(denoised(3), fresh_denoised(M::atrous, camera, *s.results[3]));
  EXPECT_EQ(denoised(5), fresh_denoised(M::svgf, camera, *s.results[5]));
  EXPECT_EQ(session.denoise(), M::svgf);
}

using testing::HalfScale;

// Keeps every frame and the views as the engine rendered them, before enlarging.
struct SmallFrames : FrameObserver {
  Session* session = nullptr;
  std::vector<std::shared_ptr<const FrameResult>> results;
  std::vector<std::vector<Framebuffer>> small;
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    results.push_back(r);
    const std::vector<Framebuffer>* scaled = session->engine(0).scaled_images();
    small.push_back(scaled ? *scaled : std::vector<Framebuffer>{});
  }
};

// `frames` frames of the box at half scale, denoised by `method` in the session.
SmallFrames run_half_scale(DenoiseMethod method, int frames) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice cpu(cache, CpuDeviceOptions{}, "cpu");
  RenderSettings settings{.spp = 1, .max_bounces = 2};
  settings.feature_buffers = true;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  lanes.push_back(balance::make_balancer("uniform", 1));
  Session session({&cpu}, std::move(lanes), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::fixed(scene.cameras[0]), settings);
  session.set_advisors([](size_t) { return std::make_unique<HalfScale>(); });
  session.set_denoise(method);
  SmallFrames s;
  s.session = &session;
  EXPECT_EQ(session.run(0, frames, s), frames);
  return s;
}

// `denoised` (a view at the rendered size) enlarged to the output's size.
Framebuffer enlarged(const Framebuffer& denoised) {
  Framebuffer out(kW, kH);
  upscale_bilinear(denoised, out);
  return out;
}

TEST(SessionDenoise, AFrameRenderedSmallerIsFilteredAtThatSizeThenEnlarged) {
  const SmallFrames s = run_half_scale(DenoiseMethod::atrous, 1);
  ASSERT_EQ(s.results.size(), 1u);
  const FrameResult& r = *s.results[0];
  ASSERT_EQ(r.record.quality.image_scale, 0.5);
  ASSERT_EQ(s.small[0].size(), 1u);
  const Framebuffer& small = s.small[0][0];
  ASSERT_EQ(small.width, kW / 2);
  ASSERT_FALSE(small.features.empty());
  ASSERT_EQ(r.denoised.size(), 1u);
  EXPECT_EQ(r.denoised[0].width, kW);
  EXPECT_EQ(r.denoised[0].height, kH);
  // enlarge(denoise(small frame)), bit for bit.
  std::vector<Framebuffer> filtered;
  FrameDenoiser(DenoiseMethod::atrous).apply({ViewSetup{}}, s.small[0], filtered);
  EXPECT_EQ(image_hash(r.denoised[0]), image_hash(enlarged(filtered.at(0))));
}

TEST(SessionDenoise, SvgfKeepsItsHistoryOverFramesRenderedSmaller) {
  constexpr int kFrames = 4;
  const SmallFrames s = run_half_scale(DenoiseMethod::svgf, kFrames);
  ASSERT_EQ(s.results.size(), size_t(kFrames));
  // One svgf history over the small frames, each result enlarged: the session's frames.
  const Camera camera = make_cornell_box().cameras[0];
  ViewSetup view;
  view.camera = camera;
  FrameDenoiser replay(DenoiseMethod::svgf);
  for (int f = 0; f < kFrames; ++f) {
    ASSERT_EQ(s.small[size_t(f)].size(), 1u);
    std::vector<Framebuffer> filtered;
    replay.apply({view}, s.small[size_t(f)], filtered);
    EXPECT_EQ(image_hash(s.results[size_t(f)]->denoised.at(0)), image_hash(enlarged(filtered[0])))
        << "frame " << f;
  }
  // ... which is not what a fresh history makes of the last frame.
  std::vector<Framebuffer> fresh;
  FrameDenoiser(DenoiseMethod::svgf).apply({view}, s.small.back(), fresh);
  EXPECT_NE(image_hash(s.results.back()->denoised.at(0)), image_hash(enlarged(fresh[0])));
}

// The frame loop's denoiser hands the frame's emission buffer to the filter: a light in
// the dark (its pixels all emission, one surface throughout, the rest black) comes out
// of atrous and svgf as it went in, its neighbours still black.
TEST(SessionDenoise, TheEmissionBufferKeepsALightSharp) {
  Framebuffer fb(kW, kH);
  fb.features.resize(kW, kH);
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const int x = int(i % kW), y = int(i / kW);
    const bool light = x >= 8 && x < 14 && y >= 5 && y < 11;
    fb.pixels[i] = light ? Vec3(17.0f, 12.0f, 4.0f) : Vec3(0.0f);
    const float v[FeatureBuffers::kFloats] = {0.78f,          0.78f,          0.78f,         0.0f,
                                              -1.0f,          0.0f,           2.0f,          0.0f,
                                              fb.pixels[i].x, fb.pixels[i].y, fb.pixels[i].z};
    fb.features.set_packed(i, v);
  }
  for (const DenoiseMethod m : {DenoiseMethod::atrous, DenoiseMethod::svgf}) {
    std::vector<Framebuffer> out;
    FrameDenoiser(m).apply({ViewSetup{}}, {fb}, out);
    for (size_t i = 0; i < fb.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out.at(0).pixels[i][c], fb.pixels[i][c]) << i;
  }
}

}  // namespace session_denoise_test
}  // namespace multiray
