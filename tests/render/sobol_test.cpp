// The path tracers' sample values (render/shared/sobol.h), Russian roulette's survival
// and the sun-or-sky choice (render/shared/sampling.h, render/environment.h).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "render/environment.h"
#include "render/shared/sampling.h"
#include "render/shared/sobol.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace sobol_test {

std::vector<Vec2> points(uint32_t pixel, uint32_t dim, uint32_t n, uint64_t seed = 0) {
  std::vector<Vec2> out;
  for (uint32_t i = 0; i < n; ++i) {
    SampleStream s = sample_stream_for_path(pixel, i, 3, 1, seed);
    s.dim = dim;
    out.push_back(sample_2d(&s));
  }
  return out;
}

// A pixel's first 2^m samples of any dimension form a (0,m,2)-net: every box of the unit
// square 2^-a wide and 2^-(m-a) high holds exactly one point (so each coordinate alone
// has one point per 1/2^m). Independent random numbers would leave about a third of the
// cells empty.
TEST(Sobol, EveryDimensionsFirstPowerOfTwoSamplesAreANet) {
  for (uint32_t pixel : {0u, 1u, 77u, 123456u, 4000000u})
    for (uint32_t dim = 0; dim < 12; ++dim)
      for (int m = 1; m <= 8; ++m) {
        const uint32_t n = 1u << m;
        const std::vector<Vec2> p = points(pixel, dim, n);
        for (int a = 0; a <= m; ++a) {
          std::set<std::pair<int, int>> cells;
          for (const Vec2& q : p) {
            ASSERT_GE(q.x, 0.0f);
            ASSERT_LT(q.x, 1.0f);
            ASSERT_GE(q.y, 0.0f);
            ASSERT_LT(q.y, 1.0f);
            cells.insert({int(std::floor(q.x * float(1 << a))),
                          int(std::floor(q.y * float(1 << (m - a))))});
          }
          ASSERT_EQ(cells.size(), n) << "pixel " << pixel << " dim " << dim << " m " << m
                                     << " boxes 2^-" << a << " x 2^-" << (m - a);
        }
      }
}

// Across pixels one sample's values are uniform (chi-square over 16 bins) and the
// dimensions are independent of one another (no correlation between a path's values of
// neighbouring dimensions, nor between a pair's two coordinates).
TEST(Sobol, ValuesAreUniformAndDimensionsUnrelatedAcrossPixels) {
  const int n = 8192, bins = 16;
  for (uint32_t sample : {0u, 5u, 16u}) {
    std::vector<double> a(n), b(n), c(n);
    std::vector<int> count(bins, 0);
    for (int i = 0; i < n; ++i) {
      SampleStream s = sample_stream_for_path(uint32_t(i), sample, 0, 0, 9);
      const Vec2 v = sample_2d(&s);
      a[size_t(i)] = v.x, b[size_t(i)] = v.y, c[size_t(i)] = sample_1d(&s);
      ++count[size_t(v.x * bins)];
    }
    double chi2 = 0;
    for (int k : count) chi2 += (k - n / bins) * (k - n / bins) / double(n / bins);
    EXPECT_LT(chi2, 37.7) << "sample " << sample;  // 15 degrees of freedom, p = 0.001
    const auto corr = [&](const std::vector<double>& x, const std::vector<double>& y) {
      double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
      for (int i = 0; i < n; ++i) {
        sx += x[size_t(i)], sy += y[size_t(i)];
        sxx += x[size_t(i)] * x[size_t(i)], syy += y[size_t(i)] * y[size_t(i)];
        sxy += x[size_t(i)] * y[size_t(i)];
      }
      const double cov = sxy / n - sx / n * sy / n;
      return cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
    };
    EXPECT_LT(std::abs(corr(a, b)), 0.05) << "sample " << sample;
    EXPECT_LT(std::abs(corr(a, c)), 0.05) << "sample " << sample;
  }
}

// Within one pixel two dimensions are shuffled against each other: the first 64 samples'
// values of dimension 1 and dimension 2 show no correlation (averaged over pixels), which
// an unshuffled index (both dimensions scrambled copies of the same points) would.
TEST(Sobol, APixelsDimensionsAreShuffledAgainstEachOther) {
  double sum = 0;
  const int pixels = 256, n = 64;
  for (int px = 0; px < pixels; ++px) {
    double sxy = 0;
    for (int i = 0; i < n; ++i) {
      SampleStream s = sample_stream_for_path(uint32_t(px), uint32_t(i), 0, 0, 0);
      s.dim = 1;
      const float x = sample_1d(&s), y = sample_1d(&s);
      sxy += (x - 0.5) * (y - 0.5);
    }
    sum += std::abs(sxy / n) * 12.0;  // |correlation| of this pixel's 64 pairs
  }
  // Independent: E|r| ~ sqrt(2 / (pi n)) = 0.10 (measured 0.13); the same index in both
  // dimensions gives 0.75.
  EXPECT_LT(sum / pixels, 0.2);
}

TEST(Sobol, ValuesArePureFunctionsOfTheirArguments) {
  const auto first = [](uint32_t px, uint32_t s, uint32_t f, uint32_t v, uint64_t seed) {
    SampleStream st = sample_stream_for_path(px, s, f, v, seed);
    const Vec2 a = sample_2d(&st);
    return std::make_pair(a.x, sample_1d(&st));
  };
  EXPECT_EQ(first(5, 3, 2, 1, 7), first(5, 3, 2, 1, 7));
  EXPECT_NE(first(5, 3, 2, 1, 7), first(6, 3, 2, 1, 7));
  EXPECT_NE(first(5, 3, 2, 1, 7), first(5, 4, 2, 1, 7));
  EXPECT_NE(first(5, 3, 2, 1, 7), first(5, 3, 3, 1, 7));
  EXPECT_NE(first(5, 3, 2, 1, 7), first(5, 3, 2, 2, 7));
  EXPECT_NE(first(5, 3, 2, 1, 7), first(5, 3, 2, 1, 8));
  SampleStream a = sample_stream_for_path(5, 3, 2, 1, 7), b = a;
  sample_stream_at_bounce(&b, 2);
  EXPECT_EQ(b.dim, MR_SOBOL_CAMERA_DIMS + 2 * MR_SOBOL_BOUNCE_DIMS);
  a.dim = b.dim;
  EXPECT_EQ(sample_1d(&a), sample_1d(&b));
}

// The figure that matters: the noise of directly lit pixels. Independent samples give
// variance(16 spp) = variance(1 spp) / 16; the sequence's stratified light and BSDF
// samples give much less (measured: a tenth of that on the Cornell box).
TEST(Sobol, DirectLightNoiseFallsFasterThanOneOverN) {
  const Scene scene = make_cornell_box();
  const int w = 32, h = 32;
  const auto variance = [&](int spp) {
    RenderSettings s;
    s.kernel = "direct";
    s.spp = spp;
    s.seed = 1;
    const Framebuffer a = testing::render_regions(scene, w, h, s, {{0, 0, w, h}});
    s.seed = 2;
    const Framebuffer b = testing::render_regions(scene, w, h, s, {{0, 0, w, h}});
    double v = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) v += 0.5 * std::pow(double(a.pixels[i][c] - b.pixels[i][c]), 2);
    return v / double(a.pixels.size() * 3);
  };
  const double v1 = variance(1), v16 = variance(16);
  EXPECT_LT(v16, 0.5 * v1 / 16) << "1 spp " << v1 << ", 16 spp " << v16;
}

// reverse_bits32 is written twice (sobol.h): the masked swaps the C++ side runs and the
// products OpenCL C runs (which clang cannot turn into llvm.bitreverse). Both are the same
// function: every byte value in every byte position (the bytes are reversed
// independently, so these fix the function), and a million other words.
TEST(SobolBits, ProductsReverseEveryWordAsTheSwapsDo) {
  for (uint32_t b = 0; b < 256; ++b) {
    ASSERT_EQ(reverse_bits8_by_products(b), reverse_bits32(b) >> 24) << b;
    for (int shift = 0; shift < 32; shift += 8)
      ASSERT_EQ(reverse_bits32_by_products(b << shift), reverse_bits32(b << shift))
          << b << " << " << shift;
  }
  uint32_t x = 12345;
  for (int i = 0; i < 1000000; ++i) {
    x = x * 1664525u + 1013904223u;
    ASSERT_EQ(reverse_bits32_by_products(x), reverse_bits32(x)) << x;
  }
  EXPECT_EQ(reverse_bits32(1u), 0x80000000u);
  EXPECT_EQ(reverse_bits32(0x12345678u), 0x1e6a2c48u);
}

// Russian roulette: the square root of the throughput, 1 from a throughput of 1 on.
TEST(RussianRoulette, SurvivalIsTheSquareRootOfTheThroughput) {
  EXPECT_FLOAT_EQ(rr_survival(0.25f), 0.5f);
  EXPECT_NEAR(rr_survival(0.125f), 0.35355f, 1e-5f);
  EXPECT_EQ(rr_survival(1.0f), 1.0f);
  EXPECT_EQ(rr_survival(3.0f), 1.0f);
  for (float b = 0.01f; b < 1.0f; b += 0.01f) EXPECT_GE(rr_survival(b), b);
}

// The sun is chosen in proportion to its irradiance against the sky's (pi x luminance),
// within [0.1, 0.9]; always without a sky.
TEST(SunChoice, ProportionalToIrradianceWithinBounds) {
  EXPECT_NEAR(sun_choice(3.0f, kPi * 0.3f), 3.0f / (3.0f + kPi * 0.3f), 1e-6f);
  EXPECT_FLOAT_EQ(sun_choice(1.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(sun_choice(1000.0f, 1.0f), 0.9f);
  EXPECT_FLOAT_EQ(sun_choice(0.001f, 1.0f), 0.1f);
  EXPECT_EQ(sun_choice(1.0f, 0.0f), 1.0f);
}

// Default daylight (sky 0.3, sun of irradiance 3 across 0.53 degrees): the light knows
// the sun's irradiance from its radiance and cone, and picks it with p = 0.761.
TEST(SunChoice, DefaultDaylightPicksTheSunThreeTimesInFour) {
  Scene scene;
  scene.environment = Vec3(0.3f);
  const float cos_half = std::cos(scene.sun.half_angle_rad);
  scene.sun.direction = normalize(Vec3(0.3f, 1.0f, 0.2f));
  scene.sun.radiance = Vec3(3.0f / (2.0f * kPi * (1.0f - cos_half)));
  const EnvironmentLight light(scene);
  EXPECT_NEAR(light.sun_irradiance(), 3.0f, 3e-3f);
  EXPECT_NEAR(light.record().p_sun, 3.0f / (3.0f + kPi * 0.3f), 1e-3f);
  scene.environment = Vec3(0.0f);
  EXPECT_EQ(EnvironmentLight(scene).record().p_sun, 1.0f);
}

}  // namespace sobol_test
}  // namespace multiray
