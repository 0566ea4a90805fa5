// The CPU filter's blocks (render/denoise_rows.h): pixels filtered several at a time get
// the bits the shared per-pixel functions give them, on every pass, at every step, next
// to every edge of the image; and the polynomial exp the weights use
// (render/shared/denoise.h's denoise_exp) is within a few ulp of exp.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "render/denoise_rows.h"
#include "render/shared/denoise_atrous.h"

namespace multiray {
namespace denoise_rows_test {

// A frame's buffers as the filter's passes read them (denoise_pack_guides's guides, a
// demodulated colour, its luminance, a variance), random but with the structure that
// gives the weights a range of values: a slanted plane of gently varying normals with a
// nearer square in front (a depth edge), a patch of another albedo, a corner of sky
// (misses), and black pixels with variance 0 (the start variance's special case).
struct PassFrame {
  int width, height;
  std::vector<float> guides, slopes, color, luminance, variance;
  std::vector<float> color_out, luminance_out, variance_out;

  PassFrame(int w, int h, unsigned seed) : width(w), height(h) {
    const size_t n = size_t(w) * size_t(h);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> albedo(3 * n), normal(3 * n), depth(n);
    color.resize(3 * n), luminance.resize(n), variance.resize(n);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        const bool front = x > w / 3 && x < w / 2 && y > h / 4 && y < 3 * h / 4;
        const bool sky = x + y < 4;
        depth[i] = sky ? INFINITY : front ? 1.0f + 0.01f * u(rng) : 2.0f + 0.02f * float(x);
        const Vec3 nrm = normalize(Vec3(0.1f * (u(rng) - 0.5f), 0.1f * (u(rng) - 0.5f), 1.0f));
        const float a = x > 2 * w / 3 ? 0.2f : 0.7f;
        for (int c = 0; c < 3; ++c) {
          normal[3 * i + size_t(c)] = sky ? 0.0f : nrm[c];
          albedo[3 * i + size_t(c)] = sky ? 0.0f : a + 0.05f * u(rng);
          color[3 * i + size_t(c)] = u(rng) < 0.1f ? 0.0f : 0.5f + u(rng);
        }
        luminance[i] = denoise_luminance(Vec3(color[3 * i], color[3 * i + 1], color[3 * i + 2]));
        variance[i] = luminance[i] == 0.0f ? 0.0f : 0.1f * u(rng);
      }
    guides.resize(MR_DENOISE_GUIDE_FLOATS * n), slopes.resize(MR_DENOISE_SLOPE_FLOATS * n);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        denoise_pack_guides(albedo.data(), normal.data(), depth.data(), w, h, x, y, guides.data(),
                            slopes.data());
    color_out.assign(3 * n, -1.0f), luminance_out.assign(n, -1.0f), variance_out.assign(n, -1.0f);
  }
  DenoisePass pass() {
    DenoisePass p;
    p.width = width, p.height = height;
    p.color = color.data(), p.luminance = luminance.data(), p.variance = variance.data();
    p.guides = guides.data(), p.slopes = slopes.data();
    p.color_out = color_out.data(), p.luminance_out = luminance_out.data();
    p.variance_out = variance_out.data();
    p.weights = denoise_weights(4.0f, 128.0f, 0.02f, 0.2f, 1);
    return p;
  }
  // Every output, to compare bit by bit.
  std::vector<float> outputs() const {
    std::vector<float> all(color_out);
    all.insert(all.end(), luminance_out.begin(), luminance_out.end());
    all.insert(all.end(), variance_out.begin(), variance_out.end());
    return all;
  }
};

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Frames whose width is and is not a multiple of the block, narrow ones with no block
// or one, and every pass: the blocks' pixels, the pixels beside them that go one by one,
// and the whole frame equal to the per-pixel functions' bit for bit. (A check that
// the frames exercise the weights: the filtered colour differs from the input.)
TEST(Denoise, BlocksComputeWhatPixelsDo) {
  const int sizes[][2] = {{67, 23}, {40, 41}, {17, 6}, {25, 9}, {7, 3}};
  for (const auto& size : sizes) {
    PassFrame blocks(size[0], size[1], 7), pixels(size[0], size[1], 7);
    const DenoisePass with = blocks.pass(), without = pixels.pass();
    for (int step = 1; step <= 16; step *= 2) {
      int by_blocks = 0;
      for (int y = 0; y < size[1]; ++y) {
        by_blocks += denoise_atrous_row(with, y, step);
        denoise_atrous_row(without, y, step, false);
      }
      EXPECT_TRUE(same_bits(blocks.outputs(), pixels.outputs()))
          << size[0] << "x" << size[1] << ", step " << step;
      if (size[0] >= 25 && step == 1) {
        EXPECT_GT(by_blocks, 0) << size[0] << "x" << size[1];
      }
      EXPECT_NE(blocks.color_out, blocks.color);
    }
    for (bool has_variance : {false, true}) {
      for (int y = 0; y < size[1]; ++y) {
        denoise_start_variance_row(with, y, has_variance);
        denoise_start_variance_row(without, y, has_variance, false);
      }
      EXPECT_TRUE(same_bits(blocks.variance_out, pixels.variance_out))
          << size[0] << "x" << size[1] << ", start variance, given " << has_variance;
    }
  }
}

// At 640 pixels a row (the size the cost is measured at) every block but the first and
// the last of each row goes as a block, at every step and in the start variance (the
// last block's pixels have taps on both sides of the right edge). At 643 the blocks
// whose taps 2 step pixels away straddle the edge go pixel by pixel too, with the 3
// pixels past the last block: at most four blocks a row.
TEST(Denoise, BlocksCoverAllButARowsEnds) {
  for (int width : {640, 643}) {
    PassFrame f(width, 70, 3);
    const DenoisePass pass = f.pass();
    const int blocks = width / kDenoiseLanes;  // whole blocks in a row
    const int most = (width == 640 ? blocks - 2 : blocks - 1) * kDenoiseLanes;
    const int least = (width == 640 ? blocks - 2 : blocks - 4) * kDenoiseLanes;
    for (int step = 1; step <= 16; step *= 2)
      for (int y : {0, 1, 35, 69}) {
        const int by_blocks = denoise_atrous_row(pass, y, step);
        EXPECT_GE(by_blocks, least) << "width " << width << ", step " << step << ", row " << y;
        EXPECT_LE(by_blocks, most) << "width " << width << ", step " << step << ", row " << y;
      }
    for (bool has_variance : {false, true})
      for (int y : {0, 2, 35, 69}) {
        const int by_blocks = denoise_start_variance_row(pass, y, has_variance);
        EXPECT_GE(by_blocks, least) << "width " << width << ", start variance, row " << y;
        EXPECT_LE(by_blocks, most) << "width " << width << ", start variance, row " << y;
      }
  }
}

// denoise_exp against exp in double over the exponents the weights take, from
// MR_DENOISE_EXP_ZERO to 0, wherever exp is a normal float: within 2 ulp (2^-22 relative;
// measured 1.2e-7, Cephes gives its expf as 1 ulp rms). Exactly 1 at 0; under FLT_MIN
// (flushed to 0 by the filter's float mode) below -87.3365.
TEST(Denoise, PolynomialExpIsWithinAFewUlps) {
  EXPECT_EQ(denoise_exp(0.0f), 1.0f);
  double worst = 0, worst_at = 0;
  const int steps = 2000000;
  for (int k = 0; k <= steps; ++k) {
    const float x = MR_DENOISE_EXP_ZERO * float(k) / float(steps);
    const double want = std::exp(double(x));
    if (want < double(FLT_MIN)) {
      EXPECT_LT(denoise_exp(x), FLT_MIN) << "at " << x;
      continue;
    }
    const double error = std::abs(double(denoise_exp(x)) - want) / want;
    if (error > worst) worst = error, worst_at = x;
  }
  EXPECT_LT(worst, std::ldexp(1.0, -22)) << "at " << worst_at;
  // Near the multiples of ln 2 / 2, where n changes.
  for (int m = -251; m <= 0; ++m) {
    const float x = float(m) * 0.34657359f;
    for (float d : {-1e-6f, 0.0f, 1e-6f}) {
      const float xd = x + d;
      if (xd < MR_DENOISE_EXP_ZERO || xd > 0.0f || std::exp(double(xd)) < double(FLT_MIN))
        continue;
      const double want = std::exp(double(xd));
      EXPECT_LT(std::abs(double(denoise_exp(xd)) - want) / want, std::ldexp(1.0, -22))
          << "at " << xd;
    }
  }
}

}  // namespace denoise_rows_test
}  // namespace multiray
