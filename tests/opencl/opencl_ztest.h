// The z-test of the OpenCL image against the CPU's (see opencl_match_test.cpp for its
// statistics), shared by the match tests: B = 32 independent images per side, per pixel
// and channel a two-sample z, summarised as the share of channels beyond |z| = 4 and the
// mean z.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "opencl_helpers.h"

namespace multiray::testing {

// 64x64 pixels: the mean z over the image has a null spread of about 1/sqrt(pixels), and at
// 32x32 (0.03-0.05 with the path tracer's heavy tails) its limit of 0.1 was only 2-3 of
// them: the CPU against itself with seed families 2000.. and 1000.. gave 0.093 on the
// textured glass box. At 64x64 every match test stays within 0.03.
constexpr int kMatchW = 64, kMatchH = 64, kMatchBatches = 32;

struct ZSummary {
  double beyond4 = 0;  // fraction of channels with |z| > 4
  double mean_z = 0;
};

inline ZSummary summarize(const std::vector<double>& z) {
  ZSummary s;
  size_t finite = 0;
  for (double v : z) {
    s.beyond4 += std::abs(v) > 4;
    if (std::isfinite(v)) s.mean_z += v, ++finite;
  }
  s.beyond4 /= double(z.size());
  s.mean_z /= double(std::max<size_t>(1, finite));
  return s;
}

// Per-pixel statistics of kMatchBatches renders with seeds first_seed, first_seed + 1, ...
inline PixelStats batches(Device& device, const Scene& scene, int spp, uint64_t first_seed) {
  PixelStats st;
  for (int b = 0; b < kMatchBatches; ++b) {
    const RenderSettings s{.spp = spp, .max_bounces = 6, .seed = first_seed + uint64_t(b)};
    st.add(render_whole(device, view_of(scene, kMatchW, kMatchH), s));
  }
  return st;
}

// The OpenCL image of `scene` against the CPU's: at most 1% of channels beyond |z| = 4,
// mean z within +-0.1. With `compact`, both devices render the compact scene.
inline ZSummary expect_matches_cpu(const Scene& scene, int spp, bool compact = false) {
  SceneCache rs(scene);
  CpuDevice cpu(rs, {.compact = compact}, "cpu");
  OpenClDevice cl(rs, {.compact = compact}, "opencl:0");
  const PixelStats ref = batches(cpu, scene, spp, 1000), got = batches(cl, scene, spp, 2000);
  const ZSummary z = summarize(z_scores(got, ref));
  EXPECT_LE(z.beyond4, 0.01) << scene.name;
  EXPECT_NEAR(z.mean_z, 0.0, 0.1) << scene.name;
  std::printf("%s: %.3f%% of channels beyond |z| = 4, mean z %.4f\n", scene.name.c_str(),
              100 * z.beyond4, z.mean_z);
  return z;
}

// The power of that test: the CPU image of `without` (the scene without the feature under
// test) against the CPU image of `with`, same seeds as above, must fail it clearly (more
// than 5% of channels beyond |z| = 4).
inline void expect_test_sees_feature(const Scene& with, const Scene& without, int spp) {
  SceneCache rs_with(with), rs_without(without);
  CpuDevice cpu_with(rs_with, {}, "cpu"), cpu_without(rs_without, {}, "cpu");
  const ZSummary z = summarize(
      z_scores(batches(cpu_without, without, spp, 2000), batches(cpu_with, with, spp, 1000)));
  std::printf("%s without the feature, on the CPU: %.3f%% of channels beyond |z| = 4\n",
              with.name.c_str(), 100 * z.beyond4);
  EXPECT_GT(z.beyond4, 0.05) << with.name;
}

// The fraction of channels of the OpenCL image within 1e-3 (relative above 1) of the
// CPU's, both rendered with the same seed: near 1 only when the kernel draws the CPU's
// random numbers in the CPU's order (a few paths diverge where an ulp flips a decision).
// With `compact`, both devices render the compact scene.
inline double same_seed_agreement(const Scene& scene, bool sample_environment = true,
                                  bool compact = false) {
  SceneCache rs(scene);
  CpuDevice cpu(rs, {.compact = compact}, "cpu");
  OpenClDevice cl(rs, {.compact = compact}, "opencl:0");
  RenderSettings s{.spp = 4, .max_bounces = 6, .seed = 5};
  s.sample_environment = sample_environment;
  const ViewSetup view = view_of(scene, kMatchW, kMatchH);
  const Framebuffer a = render_whole(cpu, view, s);
  const Framebuffer b = render_whole(cl, view, s);
  size_t close = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      close += std::abs(a.pixels[i][c] - b.pixels[i][c]) <= 1e-3f * std::max(1.0f, a.pixels[i][c]);
  const double fraction = double(close) / double(3 * a.pixels.size());
  std::printf("%s, same seed: %.2f%% of channels within 1e-3\n", scene.name.c_str(),
              100 * fraction);
  return fraction;
}

}  // namespace multiray::testing
