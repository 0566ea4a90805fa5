// Feature buffers through the engine: bit-identical for every balancer and device count
// (as the image is, engine_test.cpp), sized with the images only when a frame asks for
// them, and gone again when the next one does not; at a reduced image scale (the viewer's
// frames while the camera moves) of the output's size and right on an analytic scene; the
// viewer's refinement of progressive frames gives them as one render of all the frames'
// samples would.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "core/math.h"
#include "device/cpu/cpu_device.h"
#include "engine/engine.h"
#include "engine/half_scale_advisor.h"
#include "engine/refinement.h"
#include "engine/session.h"
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

using testing::HalfScale;

// A plane of albedo 0.5 seen level with its horizon, rendered at half size by two devices:
// the feature buffers come out at the output's size, the sky rows a miss (albedo and
// normal 0, depth +inf, never NaN), the plane's rows albedo 0.5, normal +y and the planar
// depth 1/|s_y| of each output pixel's centre (s_y its ray's slope), which 1/depth's
// interpolation reproduces (the nearest half-size pixel's depth is off by up to 9% here).
TEST(AovEngine, FeatureBuffersAtAReducedImageScaleAreOfTheOutputsSize) {
  Scene scene = make_lit_plane(0.5f, 1.0f);
  scene.cameras[0] = Camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 60.0f};
  SceneCache cache(scene);
  CpuDevice a(cache, CpuDeviceOptions{}, "cpu"), b(cache, CpuDeviceOptions{}, "cpu");
  Engine engine({&a, &b}, balance::make_balancer("queue:tile=4", 2));
  engine.set_advisor(std::make_unique<HalfScale>());
  RenderSettings settings{.spp = 4, .max_bounces = 1};
  settings.feature_buffers = true;
  constexpr int n = 32;
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = v.height = n;
  const FrameRecord rec = engine.render_frame(0, {v}, settings);
  ASSERT_EQ(rec.quality.image_scale, 0.5);
  const FeatureBuffers& f = engine.images()[0].features;
  ASSERT_EQ(f.width, n);
  ASSERT_EQ(f.height, n);
  ASSERT_EQ(f.depth.size(), size_t(n * n));
  const float tan_half = std::tan(30.0f * kPi / 180.0f);
  int plane_rows = 0;
  for (int y = 0; y < n; ++y) {
    const float slope = (1.0f - (y + 0.5f) * 2.0f / n) * tan_half;  // of the pixel centre
    // Rows whose half-size taps all see the sky (their centres above the horizon), and
    // rows well below it (not the last: its taps are clamped to the last half-size row).
    const bool sky = y < n / 2 - 1, plane = slope < -0.2f && y < n - 1;
    plane_rows += plane;
    for (int x = 0; x < n; ++x) {
      const size_t i = size_t(y * n + x);
      ASSERT_FALSE(std::isnan(f.depth[i]) || std::isnan(f.variance[i])) << x << "," << y;
      if (sky) {
        EXPECT_TRUE(std::isinf(f.depth[i])) << x << "," << y;
        EXPECT_EQ(f.albedo[3 * i], 0.0f) << x << "," << y;
        EXPECT_EQ(f.normal[3 * i + 1], 0.0f) << x << "," << y;
      }
      if (!plane) continue;
      for (size_t c = 0; c < 3; ++c)
        EXPECT_NEAR(f.albedo[3 * i + c], 0.5f, 1e-6f) << x << "," << y;
      EXPECT_NEAR(f.normal[3 * i + 1], 1.0f, 1e-5f) << x << "," << y;
      EXPECT_NEAR(f.depth[i], -1.0f / slope, 0.025f * (-1.0f / slope)) << x << "," << y;
    }
  }
  EXPECT_GE(plane_rows, 8);
}

struct Keeper : FrameObserver {
  std::vector<std::shared_ptr<const FrameResult>> results;
  void on_frame(const std::shared_ptr<const FrameResult>& r) override { results.push_back(r); }
};

// Four progressive frames of 2 samples, refined (engine/refinement.h), against one render
// of 8: the albedo is the same mean, the variance pooled exactly (to rounding), and depth
// and normal agree wherever the frames' samples all met a surface (most pixels).
TEST(AovEngine, RefinedProgressiveFramesAreOneRenderOfAllTheirSamples) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice cpu(cache, CpuDeviceOptions{}, "cpu");
  const auto frames = [&](int spp, int count) {
    RenderSettings settings{.spp = spp, .max_bounces = 4};
    settings.feature_buffers = true;
    std::vector<std::unique_ptr<balance::Balancer>> lanes;
    lanes.push_back(balance::make_balancer("uniform", 1));
    Session session({&cpu}, std::move(lanes), FrameViews(CameraRig::single(), kW, kH, {}),
                    CameraPath::fixed(scene.cameras[0]), settings);
    session.set_progressive(true);
    Keeper keep;
    session.run(0, count, keep);
    return keep.results;
  };
  const FeatureBuffers one = frames(8, 1).at(0)->images.at(0).features;
  Refinement refine(2, 8);
  const Framebuffer* shown = nullptr;
  for (const auto& f : frames(2, 4)) shown = &refine.add(f->images.at(0), RefineKey{});
  ASSERT_EQ(refine.samples(), 8);
  const FeatureBuffers& got = shown->features;
  ASSERT_EQ(got.depth.size(), one.depth.size());
  size_t same_depth = 0, varied = 0;
  for (size_t i = 0; i < one.depth.size(); ++i) {
    for (size_t c = 0; c < 3; ++c) {
      EXPECT_NEAR(got.albedo[3 * i + c], one.albedo[3 * i + c], 1e-6f);
      EXPECT_NEAR(got.emission[3 * i + c], one.emission[3 * i + c],
                  1e-5f * one.emission[3 * i + c] + 1e-7f);
    }
    EXPECT_NEAR(got.variance[i], one.variance[i], 1e-3f * one.variance[i] + 1e-7f) << i;
    varied += one.variance[i] > 1e-5f;
    same_depth += (std::isinf(one.depth[i]) && std::isinf(got.depth[i])) ||
                  std::abs(got.depth[i] - one.depth[i]) < 1e-4f * one.depth[i];
  }
  EXPECT_GT(varied, one.depth.size() / 2);
  EXPECT_GT(same_depth, one.depth.size() * 9 / 10);
}

}  // namespace aov_engine_test
}  // namespace multiray
