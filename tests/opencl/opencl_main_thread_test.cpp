// Every kernel on tiny frames, rendered on the test's own thread: the path tracer flat and
// compact, with adaptive and reprojected sample maps, and the volume raycaster. This is
// what OpenClOclgrind.* runs under Oclgrind's --uninitialized check, whose shadow memory
// (Oclgrind 21.10) crashes when a thread other than the main one writes a buffer, as the
// engine's device threads do; the multiray runs there use the other checks. On any other
// device it is a quick smoke test of each kernel (their images are checked elsewhere).
#include <gtest/gtest.h>

#include "device/opencl/opencl_denoise.h"
#include "engine/frame_views.h"
#include "opencl_helpers.h"
#include "opencl_volume_helpers.h"
#include "render/denoise_frames.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_main_thread_test {

constexpr int kW = 8, kH = 8;

// Renders every view of `views` whole on `device`, on this thread.
void render_here(OpenClDevice& device, const std::vector<ViewSetup>& views,
                 const RenderSettings& s) {
  std::vector<WorkItem> items;
  std::vector<Framebuffer> out;
  for (size_t v = 0; v < views.size(); ++v) {
    items.push_back(WorkItem{{0, 0, views[v].width, views[v].height}, int(v)});
    out.emplace_back(views[v].width, views[v].height);
  }
  ListWorkSource source(items);
  const FrameJob job{views, s, &out};
  const DeviceReport r = device.render(job, source, 0);
  EXPECT_FALSE(r.failed) << r.error;
}

TEST(OpenClMainThread, EveryKernelRendersATinyFrame) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const RenderSettings s{.spp = 1, .max_bounces = 4};
  OpenClDevice flat(rs, {.tile = 8}, "opencl:0:tile=8");
  OpenClDevice compact(rs, {.tile = 8, .compact = true}, "opencl:0:tile=8:compact=1");
  const FrameInput uniform =
      FrameViews(CameraRig::single(), kW, kH, SamplingSetup{}).make(0, scene.cameras[0]);
  render_here(flat, uniform.views, s);
  render_here(compact, uniform.views, s);

  SamplingSetup adaptive;
  adaptive.mode = Sampling::Adaptive;
  adaptive.edge_spp = 2;
  const FrameInput edges =
      FrameViews(CameraRig::single(), kW, kH, adaptive, &rs.embree()).make(0, scene.cameras[0]);
  render_here(flat, edges.views, s);

  SamplingSetup reproject;
  reproject.mode = Sampling::Reprojected;
  const FrameInput holes =
      FrameViews(CameraRig::grid(3, 1, 0.25f), kW, kH, reproject, &rs.embree())
          .make(0, scene.cameras[0]);
  render_here(flat, holes.views, s);

  const std::unique_ptr<testing::VolumeCase> c = testing::ball_case();
  OpenClDevice volume(*c->cache, {.tile = 8}, "opencl:0:tile=8");
  render_here(volume, {testing::view_of(c->scene, kW, kH)}, testing::volume_settings(*c));
}

// The denoiser's passes on an 8 x 8 frame with sky in a corner, with the variance
// estimated and given, in one launch of 64 work-items, and svgf's temporal step.
TEST(OpenClMainThread, TheDenoiserFiltersATinyFrame) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  testing::DenoiseFrame f = testing::edge_frame(testing::EdgeKind::depth, kW, kH);
  f.depth[0] = f.depth[1] = INFINITY;
  OpenClDenoiser denoiser(0, 64, 8);
  for (bool with_variance : {false, true}) {
    f.add_noise(0.3f, 1, with_variance);
    std::vector<float> out(f.beauty.size(), -1.0f);
    denoiser.atrous(f.input(), out.data());
    for (float v : out) EXPECT_GE(v, 0.0f);
  }
  // svgf's temporal kernel: a first frame, then one with a history.
  f.camera = testing::camera_at(0);
  DenoiseState state;
  for (int frame = 0; frame < 2; ++frame) {
    std::vector<float> out(f.beauty.size(), -1.0f);
    denoiser.svgf(f.input(), state, out.data());
    for (float v : out) EXPECT_GE(v, 0.0f);
  }
}

}  // namespace opencl_main_thread_test
}  // namespace multiray
