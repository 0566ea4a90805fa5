// OpenCL devices under the engine: mixed with a CPU device the image still matches the
// CPU's statistically, and an OpenCL device that fails mid-frame loses no pixel.
#include <gtest/gtest.h>

#include <cstring>

#include "balance/balancer.h"
#include "engine/engine.h"
#include "engine/frame_views.h"
#include "opencl_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_engine_test {

using testing::PixelStats;
using testing::render_whole;
using testing::view_of;

constexpr int kW = 32, kH = 32;

// Every frame of a CPU + OpenCL run is an independent image (the frame number is part of
// every path's random key), so 32 frames give 32 samples per pixel for the z-test of
// opencl_match_test.cpp, against 32 CPU-only images with other seeds. Same bounds, same
// false-alarm reasoning.
TEST(OpenClEngine, MixedCpuAndOpenClMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, {}, "cpu");
  OpenClDevice cl(rs, {}, "opencl:0");
  const int frames = 32;
  PixelStats ref, mixed;
  for (int b = 0; b < frames; ++b)
    ref.add(render_whole(cpu, view_of(scene, kW, kH),
                         RenderSettings{.spp = 8, .max_bounces = 6, .seed = 1000 + uint64_t(b)}));
  Engine engine({&cpu, &cl}, balance::make_balancer("hybrid", 2));
  uint64_t cl_pixels = 0;
  for (int f = 0; f < frames; ++f) {
    const FrameRecord rec = engine.render_frame(f, {view_of(scene, kW, kH, f)},
                                                RenderSettings{.spp = 8, .max_bounces = 6});
    ASSERT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW * kH)) << "frame " << f;
    cl_pixels += rec.devices[1].pixels;
    mixed.add(engine.images()[0]);
  }
  EXPECT_GT(cl_pixels, 0u);  // both devices took part
  const std::vector<double> z = testing::z_scores(mixed, ref);
  double beyond4 = 0, mean_z = 0;
  for (double v : z) beyond4 += std::abs(v) > 4, mean_z += std::isfinite(v) ? v : 0;
  beyond4 /= double(z.size()), mean_z /= double(z.size());
  EXPECT_LE(beyond4, 0.01);
  EXPECT_NEAR(mean_z, 0.0, 0.1);
  std::printf("mixed: %.3f%% of channels beyond |z| = 4, mean z %.4f\n", 100 * beyond4, mean_z);
}

// Progressive sampling on OpenCL (ViewSetup::first_sample, the launch's first_sample):
// four 1-spp frames that continue frame 0's sequence average, bit for bit, to its 4-spp
// render, on two devices splitting differently; four frames of their own do not.
TEST(OpenClEngine, ProgressiveFramesAverageToOneRenderOfAllTheirSamples) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  OpenClDevice a(rs, {}, "opencl:0"), b(rs, {}, "opencl:0");
  Engine engine({&a, &b}, balance::make_balancer("static:ratios=1/3", 2));
  const RenderSettings one{.spp = 1, .max_bounces = 4};
  engine.render_frame(0, {view_of(scene, kW, kH)}, RenderSettings{.spp = 4, .max_bounces = 4});
  const uint64_t whole = image_hash(engine.images()[0]);
  const auto mean_of_four = [&](bool progressive) {
    std::vector<Vec3> sum(size_t(kW) * kH, Vec3(0.0f));
    for (uint32_t k = 0; k < 4; ++k) {
      ViewSetup v = view_of(scene, kW, kH, int(k));
      if (progressive) v.first_sample = k, v.sample_frame = 0;
      engine.render_frame(int(k), {v}, one);
      for (size_t i = 0; i < sum.size(); ++i) sum[i] = sum[i] + engine.images()[0].pixels[i];
    }
    Framebuffer mean(kW, kH);
    for (size_t i = 0; i < sum.size(); ++i) mean.pixels[i] = sum[i] * 0.25f;
    return image_hash(mean);
  };
  EXPECT_EQ(mean_of_four(true), whole);
  EXPECT_NE(mean_of_four(false), whole);
}

// Reprojected sampling on two OpenCL devices: the centre view and the holes are the pixels
// of a full OpenCL render of every view, bit for bit, every other pixel is its source's,
// and only the centre and the holes are path-traced (through the devices' sample maps).
TEST(OpenClEngine, ReprojectedSamplingTracesOnlyTheCentreAndTheHoles) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  OpenClDevice a(rs, {}, "opencl:0"), b(rs, {}, "opencl:0");
  const CameraRig rig = CameraRig::grid(3, 3, 0.25f);
  const RenderSettings s{.spp = 2, .max_bounces = 4};
  const FrameInput all = FrameViews(rig, kW, kH, SamplingSetup{}).make(0, scene.cameras[0]);
  Engine full({&a, &b}, balance::make_balancer("queue:tile=8", 2));
  full.render_frame(0, all.views, s);

  SamplingSetup sampling;
  sampling.mode = Sampling::Reprojected;
  sampling.reproject_spp = s.spp;
  const FrameInput in = FrameViews(rig, kW, kH, sampling, &rs.embree()).make(0, scene.cameras[0]);
  Engine engine({&a, &b}, balance::make_balancer("dlb", 2));
  std::vector<Framebuffer> images;
  const FrameRecord rec = engine.render_frame(0, in.views, s, images);
  in.finish(images);
  const ReprojectedFrame& rf = *in.reprojection;
  const size_t n = size_t(kW) * kH;
  size_t holes = 0;
  for (size_t v = 0; v < images.size(); ++v)
    for (size_t i = 0; i < n; ++i) {
      const int32_t src = rf.is_reference(v) ? -2 : rf.maps[v].source[i];
      holes += src == ReprojectionMap::kHole;
      const Vec3& want =
          src < 0 ? full.images()[v].pixels[i]
                  : full.images()[rf.references.at(size_t(src) / n)].pixels[size_t(src) % n];
      ASSERT_EQ(std::memcmp(&images[v].pixels[i], &want, sizeof(Vec3)), 0)
          << "view " << v << " pixel " << i;
    }
  EXPECT_GT(holes, 0u);
  EXPECT_EQ(rec.devices[0].samples + rec.devices[1].samples, (n + holes) * size_t(s.spp));
}

// An OpenCL device told to fail after one unit fails when it pulls its second (in frame 0
// or, if the other device was quicker to take the work, a later one); the engine renders
// the rest of its share on the other OpenCL device and drops it. Both devices compute
// every pixel the same way, so that frame equals a healthy single-device image bit for bit.
TEST(OpenClEngine, InjectedFailureIsRecoveredBitExactly) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const RenderSettings s{.spp = 2, .max_bounces = 4};
  OpenClDevice healthy(rs, {}, "opencl:0");
  OpenClDevice failing(rs, OpenClDeviceOptions{.fail_after = 1}, "opencl:0:fail_after=1");
  Engine engine({&healthy, &failing}, balance::make_balancer("queue:tile=8", 2));
  int frame = 0;
  for (; frame < 10 && engine.alive(1); ++frame) {
    const FrameRecord rec = engine.render_frame(frame, {view_of(scene, kW, kH, frame)}, s);
    EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW * kH));
    if (engine.alive(1)) continue;
    ASSERT_EQ(rec.messages.size(), 1u);
    EXPECT_NE(rec.messages[0].find("injected failure"), std::string::npos) << rec.messages[0];
  }
  ASSERT_FALSE(engine.alive(1)) << "the failing device never failed";
  const Framebuffer reference = render_whole(healthy, view_of(scene, kW, kH, frame - 1), s);
  EXPECT_EQ(std::memcmp(engine.images()[0].pixels.data(), reference.pixels.data(),
                        reference.pixels.size() * sizeof(Vec3)),
            0)
      << "frame " << frame - 1;
  // The next frame runs on the survivor alone.
  const FrameRecord next = engine.render_frame(frame, {view_of(scene, kW, kH, frame)}, s);
  EXPECT_EQ(next.devices[0].pixels, uint64_t(kW * kH));
}

}  // namespace opencl_engine_test
}  // namespace multiray
