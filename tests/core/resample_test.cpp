#include "core/resample.h"

#include <gtest/gtest.h>

namespace multiray {
namespace {

// A half-size image of f(x, y) = a x + b y at its pixel centres, in output pixel units.
Framebuffer ramp(int w, int h, float scale) {
  Framebuffer fb(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float cx = (x + 0.5f) * scale, cy = (y + 0.5f) * scale;
      fb.at(x, y) = Vec3{cx, cy, 2.0f * cx - 3.0f * cy};
    }
  return fb;
}

TEST(Resample, ReproducesALinearFunctionBetweenTheCentres) {
  // 10 x 6 -> 20 x 12: output centres (x + 0.5) sample the ramp at exactly x + 0.5.
  const Framebuffer small = ramp(10, 6, 2.0f);
  Framebuffer big(20, 12);
  upscale_bilinear(small, big);
  for (int y = 1; y < 11; ++y)  // rows and columns past the outermost centres are clamped
    for (int x = 1; x < 19; ++x) {
      const float cx = x + 0.5f, cy = y + 0.5f;
      EXPECT_NEAR(big.at(x, y).x, cx, 1e-5f) << x << "," << y;
      EXPECT_NEAR(big.at(x, y).y, cy, 1e-5f) << x << "," << y;
      EXPECT_NEAR(big.at(x, y).z, 2.0f * cx - 3.0f * cy, 1e-4f) << x << "," << y;
    }
  // Beyond the outermost centres the edge value is held.
  EXPECT_FLOAT_EQ(big.at(0, 5).x, small.at(0, 2).x);
  EXPECT_FLOAT_EQ(big.at(19, 5).x, small.at(9, 2).x);
}

TEST(Resample, KeepsConstantsAndCopiesEqualSizes) {
  Framebuffer one(1, 1), out(7, 5);
  one.at(0, 0) = Vec3{0.25f, 0.5f, 4.0f};
  upscale_bilinear(one, out);
  for (const Vec3& p : out.pixels) {
    EXPECT_EQ(p.x, 0.25f);
    EXPECT_EQ(p.y, 0.5f);
    EXPECT_EQ(p.z, 4.0f);
  }
  // A ratio that is not an integer (the 0.82 scale of the volume runs) stays within the
  // source's range and reproduces the ramp inside.
  const Framebuffer small = ramp(41, 23, 1.0f);
  Framebuffer big(50, 28);
  upscale_bilinear(small, big);
  const double rx = 41.0 / 50.0, ry = 23.0 / 28.0;
  for (int y = 2; y < 26; ++y)
    for (int x = 2; x < 48; ++x) {
      EXPECT_NEAR(big.at(x, y).x, (x + 0.5) * rx, 1e-4) << x;
      EXPECT_NEAR(big.at(x, y).y, (y + 0.5) * ry, 1e-4) << y;
    }
  Framebuffer same(41, 23);
  upscale_bilinear(small, same);
  for (size_t i = 0; i < small.pixels.size(); ++i) {
    EXPECT_EQ(same.pixels[i].x, small.pixels[i].x);
    EXPECT_EQ(same.pixels[i].z, small.pixels[i].z);
  }
}

}  // namespace
}  // namespace multiray

namespace multiray {
namespace {

// An RGBA layer (the shadow catcher's) keeps its alpha through the upscale, interpolated
// like the colour; an image without alpha gets none.
TEST(Resample, InterpolatesAlphaWithTheColour) {
  Framebuffer small(2, 1);
  small.pixels = {Vec3(0.0f), Vec3(1.0f)};
  small.alpha = {0.0f, 1.0f};
  Framebuffer big(4, 1);
  upscale_bilinear(small, big);
  ASSERT_EQ(big.alpha.size(), 4u);
  for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(big.alpha[size_t(x)], big.at(x, 0).x);
  EXPECT_EQ(big.alpha[0], 0.0f);
  EXPECT_EQ(big.alpha[3], 1.0f);
  Framebuffer same(2, 1);
  upscale_bilinear(small, same);
  EXPECT_EQ(same.alpha, small.alpha);
  Framebuffer plain(2, 1), out(4, 1);
  upscale_bilinear(plain, out);
  EXPECT_TRUE(out.alpha.empty());
}

}  // namespace
}  // namespace multiray
