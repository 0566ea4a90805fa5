// Multiview (light-field) rendering: every view is independent of how work was split,
// for both task mappings, and the rig places parallel views on a grid.
#include <gtest/gtest.h>

#include <cstring>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/engine.h"
#include "scene/builders.h"
#include "scene/camera_rig.h"

namespace multiray {
namespace multiview_test {

constexpr int kW = 37, kH = 23;

std::vector<ViewSetup> grid_views(const Scene& s, const CameraRig& rig, int frame) {
  std::vector<ViewSetup> out;
  for (const Camera& c : rig.views(s.cameras[0])) {
    ViewSetup v;
    v.camera = c;
    v.width = kW, v.height = kH, v.frame = uint32_t(frame), v.view = uint32_t(out.size());
    out.push_back(v);
  }
  return out;
}

std::vector<Framebuffer> render(SceneCache& rs, const std::string& spec, int devices) {
  std::vector<std::unique_ptr<CpuDevice>> owned;
  std::vector<Device*> ptrs;
  for (int i = 0; i < devices; ++i) {
    owned.push_back(std::make_unique<CpuDevice>(rs, CpuDeviceOptions{}, "cpu"));
    ptrs.push_back(owned.back().get());
  }
  Engine engine(ptrs, balance::make_balancer(spec, devices));
  const CameraRig rig = CameraRig::grid(3, 2, 0.2f);
  for (int f = 0; f < 2; ++f) {
    const FrameRecord rec =
        engine.render_frame(f, grid_views(rs.scene(), rig, f), RenderSettings{.spp = 1});
    uint64_t pixels = 0;
    for (const auto& d : rec.devices) pixels += d.pixels;
    EXPECT_EQ(pixels, uint64_t(kW) * kH * 6) << spec;
  }
  return engine.images();
}

TEST(Multiview, ViewsAreBitIdenticalForEveryMappingAndDeviceCount) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const auto reference = render(rs, "uniform", 1);
  ASSERT_EQ(reference.size(), 6u);
  // The views differ from each other (the rig moves the camera).
  EXPECT_NE(std::memcmp(reference[0].pixels.data(), reference[5].pixels.data(),
                        reference[0].pixels.size() * sizeof(Vec3)),
            0);
  for (const std::string spec : {"dlb", "dlb:layout=views", "uniform:layout=views",
                                 "uniform:layout=strips", "hybrid", "semi-static", "queue"})
    for (int devices : {2, 4}) {
      const auto images = render(rs, spec, devices);
      for (size_t v = 0; v < images.size(); ++v)
        EXPECT_EQ(std::memcmp(images[v].pixels.data(), reference[v].pixels.data(),
                              images[v].pixels.size() * sizeof(Vec3)),
                  0)
            << spec << " on " << devices << " devices, view " << v;
    }
}

TEST(CameraRig, GridViewsAreParallelAndSpaced) {
  const Camera c{{0, 1, 4}, {0, 1, 0}, {0, 1, 0}, 40};
  const auto views = CameraRig::grid(3, 3, 0.2f).views(c);
  ASSERT_EQ(views.size(), 9u);
  EXPECT_NEAR(length(views[4].eye - c.eye), 0.0f, 1e-6f);  // the centre view is the camera
  EXPECT_NEAR(length(views[1].eye - views[0].eye), 0.2f, 1e-5f);
  EXPECT_NEAR(length(views[3].eye - views[0].eye), 0.2f, 1e-5f);
  EXPECT_LT(views[0].eye.x, views[2].eye.x);  // left to right
  EXPECT_GT(views[0].eye.y, views[6].eye.y);  // top row first
  for (const Camera& v : views) {
    const Vec3 d = normalize(v.target - v.eye);
    EXPECT_NEAR(dot(d, normalize(c.target - c.eye)), 1.0f, 1e-6f);  // parallel
  }
  const auto stereo = CameraRig::stereo(0.064f).views(c);
  ASSERT_EQ(stereo.size(), 2u);
  EXPECT_NEAR(stereo[1].eye.x - stereo[0].eye.x, 0.064f, 1e-6f);
}

}  // namespace multiview_test
}  // namespace multiray
