// Feature buffers through the engine: bit-identical for every balancer and device count
// (as the image is, engine_test.cpp), sized with the images only when a frame asks for
// them, and gone again when the next one does not.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/engine.h"
#include "scene/builders.h"

namespace multiray {
namespace aov_engine_test {

constexpr int kW = 45, kH = 27;

std::vector<ViewSetup> views(const Scene& s, int frame) {
  ViewSetup v;
  v.camera = s.cameras[0];
  v.width = kW, v.height = kH, v.frame = uint32_t(frame);
  return {v};
}

// Renders frames 0 and 1 (the second plan is made from measurements) and returns the
// feature hash of the last frame's buffers (and its image's in *image).
uint64_t features_with(SceneCache& rs, const std::string& spec, int devices, uint64_t* image) {
  std::vector<std::unique_ptr<CpuDevice>> owned;
  std::vector<Device*> ptrs;
  for (int i = 0; i < devices; ++i) {
    owned.push_back(std::make_unique<CpuDevice>(rs, CpuDeviceOptions{}, "cpu"));
    ptrs.push_back(owned.back().get());
  }
  Engine engine(ptrs, balance::make_balancer(spec, devices));
  RenderSettings settings{.spp = 2, .max_bounces = 4};
  settings.feature_buffers = true;
  for (int f = 0; f < 2; ++f) engine.render_frame(f, views(rs.scene(), f), settings);
  const Framebuffer& img = engine.images()[0];
  EXPECT_EQ(img.features.width, kW) << spec;
  *image = image_hash(img);
  return feature_hash(img.features);
}

TEST(AovEngine, FeatureBuffersAreBitIdenticalForEveryBalancerAndDeviceCount) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  uint64_t reference_image = 0;
  const uint64_t reference = features_with(rs, "uniform", 1, &reference_image);
  for (const std::string& name : balance::balancer_names())
    for (int devices : {2, 3}) {
      uint64_t image = 0;
      EXPECT_EQ(features_with(rs, name, devices, &image), reference)
          << name << " on " << devices << " devices";
      EXPECT_EQ(image, reference_image) << name << " on " << devices << " devices";
    }
}

TEST(AovEngine, BuffersOnlyForTheFramesThatAskForThem) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, CpuDeviceOptions{}, "cpu");
  Engine engine({&cpu}, balance::make_balancer("uniform", 1));
  RenderSettings plain{.spp = 1, .max_bounces = 2};
  engine.render_frame(0, views(scene, 0), plain);
  EXPECT_TRUE(engine.images()[0].features.empty());
  RenderSettings with = plain;
  with.feature_buffers = true;
  engine.render_frame(1, views(scene, 1), with);
  EXPECT_EQ(engine.images()[0].features.depth.size(), size_t(kW * kH));
  engine.render_frame(2, views(scene, 2), plain);
  EXPECT_TRUE(engine.images()[0].features.empty());
  EXPECT_TRUE(engine.images()[0].features.albedo.empty());
}

}  // namespace aov_engine_test
}  // namespace multiray
