// Exposure and the filmic tone curve of PNG output (core/image.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/image.h"

namespace multiray {
namespace tone_test {

TEST(ToneCurve, FilmicIsMonotoneFromZeroAndSaturates) {
  EXPECT_EQ(tone_filmic(0.0f), 0.0f);
  float prev = 0.0f;
  for (float x = 1e-4f; x < 100.0f; x *= 1.01f) {
    const float y = tone_filmic(x);
    ASSERT_GE(y, prev) << "x = " << x;
    ASSERT_LE(y, 1.0f) << "x = " << x;
    prev = y;
  }
  // Strictly rising below the shoulder, so nothing below it is lost.
  EXPECT_LT(tone_filmic(1.0f), tone_filmic(2.0f));
  EXPECT_LT(tone_filmic(4.0f), tone_filmic(6.0f));
  EXPECT_LT(tone_filmic(6.0f), 1.0f);
  // Saturates: white from about 7.24 (where the fit crosses 1) on, and for huge values.
  EXPECT_EQ(tone_filmic(7.3f), 1.0f);
  EXPECT_EQ(tone_filmic(1e30f), 1.0f);
  EXPECT_EQ(tone_filmic(INFINITY), 1.0f);
  // The fit's values at mid grey and at 1 (worked out by hand from the formula).
  EXPECT_NEAR(tone_filmic(0.18f), 0.2669f, 1e-3f);
  EXPECT_NEAR(tone_filmic(1.0f), 0.8038f, 1e-3f);
  // Nothing negative or NaN reaches the image.
  EXPECT_EQ(tone_filmic(-1.0f), 0.0f);
  EXPECT_EQ(tone_filmic(NAN), 0.0f);
}

TEST(ToneCurve, ExposureInStopsScalesLinearRadiance) {
  EXPECT_EQ(exposure_scale(0.0f), 1.0f);
  EXPECT_EQ(exposure_scale(1.0f), 2.0f);
  EXPECT_EQ(exposure_scale(-2.0f), 0.25f);
  for (ToneCurve tone : {ToneCurve::Clamp, ToneCurve::Filmic})
    for (float x : {0.0f, 0.01f, 0.1f, 0.3f, 0.45f, 2.0f}) {
      // +1 EV on x shows exactly what 0 EV shows on 2x.
      EXPECT_EQ(display_value(x, {1.0f, tone}), display_value(2.0f * x, {0.0f, tone})) << x;
      EXPECT_EQ(display_value(x, {-1.0f, tone}), display_value(0.5f * x, {0.0f, tone})) << x;
    }
  // Clamp at 0 EV is the identity on [0, 1].
  EXPECT_EQ(display_value(0.25f, {}), 0.25f);
  EXPECT_EQ(display_value(3.0f, {}), 1.0f);
}

TEST(ToneCurve, PngBytesUnderClampAndFilmic) {
  Framebuffer fb(4, 1);
  fb.pixels = {Vec3(0.0f), Vec3(0.5f), Vec3(1.0f), Vec3(4.0f)};
  // Clamp at 0 EV: the encoding of earlier releases (sRGB of the clipped value).
  const std::vector<uint8_t> clamp = to_srgb8(fb);
  EXPECT_EQ(clamp[0], 0);
  EXPECT_EQ(clamp[3], 188);
  EXPECT_EQ(clamp[6], 255);
  EXPECT_EQ(clamp[9], 255);  // 4 clips to white
  // Filmic keeps 1 and 4 apart, both below white; +1 EV brightens.
  const std::vector<uint8_t> filmic = to_srgb8(fb, {0.0f, ToneCurve::Filmic});
  EXPECT_EQ(filmic[0], 0);
  EXPECT_LT(filmic[6], filmic[9]);
  EXPECT_LT(filmic[9], 255);
  const std::vector<uint8_t> brighter = to_srgb8(fb, {1.0f, ToneCurve::Filmic});
  EXPECT_GT(brighter[3], filmic[3]);
  EXPECT_EQ(brighter[3], filmic[6]);  // 0.5 at +1 EV is 1 at 0 EV
}

}  // namespace tone_test
}  // namespace multiray
