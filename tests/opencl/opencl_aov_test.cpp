// The feature buffers (AOVs, render/shared/aov.h) on the OpenCL device: the analytic
// plane's values, the CPU's buffers to float tolerance (the same code on the same random
// numbers), bit-identical for any split, launch size and device count, and the beauty the
// same bits with and without them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/feature_buffers.h"
#include "opencl_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_aov_test {

using testing::render_on;
using testing::render_whole;
using testing::view_of;

RenderSettings with_features(int spp) {
  RenderSettings s;
  s.spp = spp;
  s.max_bounces = 5;
  s.seed = 7;
  s.feature_buffers = true;
  return s;
}

// A diffuse plane of albedo 0.5 facing +y, seen straight down from height 1.
TEST(OpenClAov, PlaneSeenFromAbove) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache rs(scene);
  OpenClDevice cl(rs, {}, "opencl:0");
  const Framebuffer fb = render_whole(cl, view_of(scene, 24, 16), with_features(4));
  const FeatureBuffers& f = fb.features;
  ASSERT_EQ(f.depth.size(), size_t(24 * 16));
  for (size_t i = 0; i < f.depth.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f.albedo[3 * i + size_t(c)], 0.5f) << i;
    EXPECT_NEAR(f.normal[3 * i + 1], 1.0f, 1e-6f) << i;
    EXPECT_NEAR(f.depth[i], 1.0f, 1e-4f) << i;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f.emission[3 * i + size_t(c)], 0.0f) << i;
  }
}

// A pixel that sees only a light (the plane emits and reflects nothing): its emission is
// the beauty, bit for bit, also under the sample clamp (aov.h).
TEST(OpenClAov, EmissionOfALightSeenDirectlyIsTheBeauty) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = make_lit_plane(0.0f, 1.0f);
  scene.materials[0].emission = Vec3(4.0f, 2.0f, 1.0f);
  SceneCache rs(scene);
  OpenClDevice cl(rs, {}, "opencl:0");
  for (const float clamp : {0.0f, 3.0f}) {
    RenderSettings s = with_features(4);
    s.sample_clamp = clamp;
    const Framebuffer fb = render_whole(cl, view_of(scene, 12, 8), s);
    for (size_t i = 0; i < fb.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(fb.features.emission[3 * i + size_t(c)], fb.pixels[i][c]) << i << " " << clamp;
        EXPECT_GT(fb.pixels[i][c], 0.0f);
      }
  }
}

// The same code on the same random numbers: albedo, normal, depth and emission (fixed by
// the camera ray and the specular bounces after it) agree to float rounding nearly
// everywhere; the variance (of the whole path) agrees where the two backends' paths did,
// which is most pixels.
TEST(OpenClAov, MatchesCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const ViewSetup view = view_of(scene, 48, 32);
  const RenderSettings s = with_features(4);
  CpuDevice cpu(rs, {}, "cpu");
  OpenClDevice cl(rs, {}, "opencl:0");
  const FeatureBuffers a = render_whole(cpu, view, s).features,
                       b = render_whole(cl, view, s).features;
  ASSERT_EQ(a.depth.size(), b.depth.size());
  const auto close = [](float x, float y, float tol) {
    return (std::isinf(x) && x == y) || std::abs(x - y) <= tol * std::max(1.0f, std::abs(x));
  };
  size_t geometry = 0, variance = 0, emission = 0, emitting = 0;
  const size_t n = a.depth.size();
  for (size_t i = 0; i < n; ++i) {
    bool same = close(a.depth[i], b.depth[i], 1e-4f), same_emission = true;
    for (int c = 0; c < 3; ++c) {
      same &= close(a.albedo[3 * i + size_t(c)], b.albedo[3 * i + size_t(c)], 1e-4f);
      same &= close(a.normal[3 * i + size_t(c)], b.normal[3 * i + size_t(c)], 1e-4f);
      same_emission &= close(a.emission[3 * i + size_t(c)], b.emission[3 * i + size_t(c)], 1e-4f);
    }
    geometry += same;
    variance += close(a.variance[i], b.variance[i], 1e-3f);
    emission += same_emission;
    emitting += a.emission[3 * i] > 0.0f;
  }
  EXPECT_GE(double(geometry), 0.99 * double(n));
  EXPECT_GE(double(variance), 0.9 * double(n));
  EXPECT_GE(double(emission), 0.99 * double(n));
  EXPECT_GT(emitting, 0u);  // the light is in view
}

// Split independence: tiles, small launches (tile=4, wg=1), two devices pulling
// concurrently: the buffers' bits are the whole frame's. The beauty's bits are those of
// a render without feature buffers.
TEST(OpenClAov, BitIdenticalForAnySplit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 37, h = 23;
  const ViewSetup view = view_of(scene, w, h, 3);
  const RenderSettings s = with_features(2);
  OpenClDevice a(rs, {}, "opencl:0");
  const Framebuffer whole = render_whole(a, view, s);
  RenderSettings plain = s;
  plain.feature_buffers = false;
  EXPECT_EQ(image_hash(render_whole(a, view, plain)), image_hash(whole)) << "beauty";

  std::vector<Rect> tiles;
  for (int y = 0; y < h; y += 5)
    for (int x = 0; x < w; x += 7) tiles.push_back({x, y, std::min(w, x + 7), std::min(h, y + 5)});
  const uint64_t expected = feature_hash(whole.features);
  EXPECT_EQ(feature_hash(render_on({&a}, view, s, tiles).features), expected) << "tiles";
  OpenClDevice b(rs, OpenClDeviceOptions{.tile = 4, .work_group = 1}, "opencl:0:tile=4:wg=1");
  EXPECT_EQ(feature_hash(render_whole(b, view, s).features), expected) << "tile=4 wg=1";
  EXPECT_EQ(feature_hash(render_on({&a, &b}, view, s, tiles).features), expected) << "two";
}

}  // namespace opencl_aov_test
}  // namespace multiray
