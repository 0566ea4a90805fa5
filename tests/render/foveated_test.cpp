// Foveated sampling (Harada & Fujita 2014): the pattern, the per-frame neighbour lists and
// radii, and the reconstruction of pixels from samples.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <random>
#include <set>

#include "render/foveated.h"
#include "scene/builders.h"

namespace multiray {
namespace foveated_test {

// Renders `rect` of a foveated view of `scene` with the kernel, on the calling thread.
Framebuffer render_foveated(const Scene& scene, const FoveationFrame& f, RenderSettings s,
                            Rect rect = {}) {
  SceneCache scenes(scene);
  const std::unique_ptr<Kernel> sampled = find_cpu_kernel(s.kernel)->make(scenes, false);
  const FoveatedKernel kernel(*sampled);
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = f.width, v.height = f.height, v.foveation = &f;
  Framebuffer fb(f.width, f.height);
  for (Vec3& p : fb.pixels) p = Vec3(NAN);  // a pixel left unwritten stays NaN
  if (rect.area() == 0) rect = {0, 0, f.width, f.height};
  std::vector<Vec3> scratch;
  kernel.render_rect(v, s, rect, fb, scratch);
  return fb;
}

// The pattern is the same every time, holds the gaze sample first, and its density
// follows density(r): about fovea_spp near the gaze, the floor far away.
TEST(FoveatedPattern, DeterministicWithDensityFallingOffToTheFloor) {
  const FoveationParams p;  // 4 spp at the gaze, r0 = 0.1 of the height, floor 1/16
  const FoveationPattern a = make_foveation_pattern(320, 200, p);
  const FoveationPattern b = make_foveation_pattern(320, 200, p);
  ASSERT_EQ(a.offsets.size(), b.offsets.size());
  for (size_t i = 0; i < a.offsets.size(); ++i)
    ASSERT_TRUE(a.offsets[i].x == b.offsets[i].x && a.offsets[i].y == b.offsets[i].y);
  EXPECT_EQ(a.offsets[0].x, 0.0f);
  EXPECT_EQ(a.offsets[0].y, 0.0f);
  // Within r0/4 (density 4/(1+1/16) ≈ 3.8) and a far square (density 1/16).
  const float r0 = 0.1f * 200;
  double inner = 0, far = 0;
  for (const Vec2& o : a.offsets) {
    inner += std::hypot(o.x, o.y) < 0.25f * r0;
    far += o.x >= 200 && o.x < 300 && o.y >= 100 && o.y < 180;
  }
  const double inner_area = kPi * 0.0625 * r0 * r0;
  EXPECT_NEAR(inner / inner_area, 3.8, 0.5);
  EXPECT_NEAR(far / (100.0 * 80.0), 1.0 / 16.0, 0.01);
  // Covers [-w, w) x [-h, h).
  float lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
  for (const Vec2& o : a.offsets)
    lo_x = std::min(lo_x, o.x), hi_x = std::max(hi_x, o.x), lo_y = std::min(lo_y, o.y),
    hi_y = std::max(hi_y, o.y);
  EXPECT_LT(lo_x, -310.0f);
  EXPECT_GT(hi_x, 310.0f);
  EXPECT_LT(lo_y, -190.0f);
  EXPECT_GT(hi_y, 190.0f);
}

// A plane under an open sky seen straight down: every AO sample is exactly 1, and every
// pixel reconstructs to exactly 1. With the path tracer every sample is albedo·sky up to
// rounding of the BSDF weight; pixels stay within that rounding.
TEST(FoveatedReconstruction, ConstantSceneIsExact) {
  const Scene plane = make_lit_plane(0.5f, 1.0f);
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(48, 32, {}), 0.3f, 0.6f);
  RenderSettings s;
  s.kernel = "ao";
  s.ao_rays = 2;
  s.ao_distance = 5.0f;
  for (const Vec3& p : render_foveated(plane, f, s).pixels) ASSERT_EQ(p.x, 1.0f);
  s.kernel = "path";
  s.max_bounces = 1;
  for (const Vec3& p : render_foveated(plane, f, s).pixels)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], 0.5f, 1e-6f);
  // Any constant, fed to the reconstruction directly, comes out bit for bit.
  const std::vector<Vec3> values(f.size(), Vec3(0.3f, 1.7f, 123.456f));
  Framebuffer fb(f.width, f.height);
  reconstruct_rect(f, values.data(), {0, 0, f.width, f.height}, fb);
  for (const Vec3& p : fb.pixels) ASSERT_TRUE(p.x == 0.3f && p.y == 1.7f && p.z == 123.456f);
}

// Samples of a linear function g(x, y) = a·x + b·y + c. The reconstruction is a convex
// combination of the k neighbours' values, so its error at a pixel centre q is at most
// |∇g| · max_j |p_j − q| (the farthest neighbour's distance): that bound must hold at
// every pixel. On average the error is far smaller, as the neighbours surround the pixel
// and their offsets partly cancel: the mean error must stay under 0.5 |∇g| (half the
// step between neighbouring pixels; measured 0.37 with samples ~4 px apart in the
// periphery) and under 0.15 |∇g| inside the fovea (measured 0.09).
TEST(FoveatedReconstruction, LinearGradientStaysWithinBound) {
  const int w = 160, h = 90;
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(w, h, {}), 0.4f, 0.5f);
  const float a = 0.02f, b = -0.013f, c = 0.5f, grad = std::hypot(a, b);
  std::vector<Vec3> values(f.size());
  for (size_t s = 0; s < f.size(); ++s)
    values[s] = Vec3(a * f.position[s].x + b * f.position[s].y + c);
  Framebuffer fb(w, h);
  reconstruct_rect(f, values.data(), {0, 0, w, h}, fb);
  double sum = 0, fovea_sum = 0;
  int fovea_n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float qx = x + 0.5f, qy = y + 0.5f;
      const float exact = a * qx + b * qy + c;
      float farthest = 0;
      const uint32_t* nb = f.neighbours_of(x, y);
      for (int j = 0; j < f.k && nb[j] != FoveationFrame::kNoSample; ++j)
        farthest =
            std::max(farthest, std::hypot(f.position[nb[j]].x - qx, f.position[nb[j]].y - qy));
      const float err = std::abs(fb.at(x, y).x - exact);
      ASSERT_LE(err, grad * farthest + 1e-5f) << x << "," << y;
      sum += err;
      if (std::hypot(qx - f.gaze.x, qy - f.gaze.y) < 0.1f * h) fovea_sum += err, ++fovea_n;
    }
  EXPECT_LT(sum / (w * h), 0.5 * grad);
  ASSERT_GT(fovea_n, 50);
  EXPECT_LT(fovea_sum / fovea_n, 0.15 * grad);
}

// Shepard's interpolation, recomputed here from the positions alone: every pixel is the
// mean of its k nearest samples (found by brute force) weighted by inverse squared
// distance, for arbitrary sample values. (A reconstruction that skipped a neighbour kept
// constants exact and gradients within bound; this does not let it pass.)
TEST(FoveatedReconstruction, EachPixelIsTheShepardMeanOfItsKNearestSamples) {
  const int w = 40, h = 24;
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(w, h, {}), 0.35f, 0.55f);
  ASSERT_GT(f.k, 2);
  std::vector<Vec3> values(f.size());
  for (size_t s = 0; s < f.size(); ++s) values[s] = Vec3(float((s * 7919) % 101) / 10.0f);
  Framebuffer fb(w, h);
  reconstruct_rect(f, values.data(), {0, 0, w, h}, fb);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double qx = x + 0.5, qy = y + 0.5;
      std::vector<std::pair<double, size_t>> by_distance;
      for (size_t s = 0; s < f.size(); ++s)
        by_distance.push_back(
            {std::pow(f.position[s].x - qx, 2) + std::pow(f.position[s].y - qy, 2), s});
      std::sort(by_distance.begin(), by_distance.end());
      double sum = 0, weights = 0;
      for (int j = 0; j < f.k && j < int(by_distance.size()); ++j) {
        const double wj = 1.0 / std::max(by_distance[size_t(j)].first, 1e-12);
        sum += wj * values[by_distance[size_t(j)].second].x;
        weights += wj;
      }
      ASSERT_NEAR(fb.at(x, y).x, sum / weights, 1e-3 * (1.0 + sum / weights)) << x << "," << y;
    }
}

// No holes: every pixel has a neighbour and gets a finite value, at tiny and odd sizes and
// with the gaze in the corners, where most of the screen is periphery.
TEST(FoveatedReconstruction, EveryPixelGetsAValue) {
  const Scene scene = make_cornell_box();
  RenderSettings s;
  s.kernel = "ao";
  const std::pair<int, int> sizes[] = {{1, 1}, {2, 1}, {1, 3}, {7, 5}, {33, 17}, {97, 61}};
  const std::pair<float, float> gazes[] = {{0.5f, 0.5f}, {0, 0}, {1, 1}, {1, 0}, {0.1f, 0.9f}};
  for (const auto& [w, h] : sizes) {
    const FoveationPattern pattern = make_foveation_pattern(w, h, {});
    for (const auto& [gx, gy] : gazes) {
      const FoveationFrame f = prepare_foveation_frame(pattern, gx, gy);
      ASSERT_GE(f.size(), 1u);
      for (size_t p = 0; p < size_t(w * h); ++p)
        ASSERT_NE(f.neighbours[p * size_t(f.k)], FoveationFrame::kNoSample);
      for (const Vec3& p : render_foveated(scene, f, s).pixels)
        ASSERT_TRUE(is_finite(p)) << w << "x" << h << " gaze " << gx << "," << gy;
    }
  }
}

// The radius rule: for any rect, the samples selected by disc ∩ rect include every
// neighbour of every pixel of the rect; and every used sample is counted in exactly one
// pixel of the cost map.
TEST(FoveatedFrame, RectSelectionHoldsEveryNeighbourOfItsPixels) {
  const int w = 123, h = 77;
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(w, h, {}), 0.7f, 0.2f);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int x0 = int(rng() % w), y0 = int(rng() % h);
    const int x1 = x0 + 1 + int(rng() % (w - x0)), y1 = y0 + 1 + int(rng() % (h - y0));
    const std::vector<uint32_t> sel = select_samples(f, {x0, y0, x1, y1});
    const std::set<uint32_t> selected(sel.begin(), sel.end());
    ASSERT_EQ(selected.size(), sel.size());  // no sample twice
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const uint32_t* nb = f.neighbours_of(x, y);
        for (int j = 0; j < f.k && nb[j] != FoveationFrame::kNoSample; ++j)
          ASSERT_TRUE(selected.count(nb[j])) << "pixel " << x << "," << y << " in rect " << x0
                                             << "," << y0 << "-" << x1 << "," << y1;
      }
  }
  double weight = 0;
  for (float v : f.pixel_samples) weight += v;
  EXPECT_EQ(weight, double(f.used_samples));
  EXPECT_EQ(select_samples(f, {0, 0, w, h}).size(), f.used_samples);
}

}  // namespace foveated_test
}  // namespace multiray
