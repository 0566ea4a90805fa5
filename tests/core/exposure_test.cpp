// Automatic exposure (core/exposure.h): a meter that maps the log-average luminance to
// middle grey, reading zones rather than single noisy pixels and leaving black out.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/exposure.h"

namespace exposure_test {

using multiray::Framebuffer;
using multiray::kMeterKey;
using multiray::kMeterMaxStops;
using multiray::metered_exposure_ev;
using multiray::Vec3;

Framebuffer grey(int w, int h, float l) {
  Framebuffer fb(w, h);
  for (Vec3& p : fb.pixels) p = Vec3(l, l, l);
  return fb;
}

// A grey image of luminance L is brought to the key exactly: EV = log2(key / L).
TEST(Exposure, AGreyImageIsBroughtToMiddleGrey) {
  for (float l : {0.01f, 0.045f, 0.18f, 3.0f})
    EXPECT_NEAR(metered_exposure_ev(grey(64, 40, l)), std::log2(kMeterKey / l), 1e-4) << l;
}

// Black (a background where nothing shines) is not read: half an image black meters as the
// other half alone. Counted, it would have asked for several more stops.
TEST(Exposure, BlackIsLeftOut) {
  Framebuffer fb = grey(96, 96, 0.045f);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 48; ++x) fb.at(x, y) = Vec3(0, 0, 0);
  EXPECT_NEAR(metered_exposure_ev(fb), 2.0, 0.05);
}

// A path tracer's noise: each pixel is 4L with probability 1/4, else black (mean L). Zones
// average it first, so the meter reads about L; pixel by pixel it would read 4L (two stops
// darker) since the black pixels are left out.
TEST(Exposure, NoiseIsAveragedInZonesBeforeTheLog) {
  Framebuffer fb(640, 360);
  std::mt19937 rng(7);
  std::bernoulli_distribution lit(0.25);
  const float l = 0.045f;
  for (Vec3& p : fb.pixels) p = lit(rng) ? Vec3(4 * l, 4 * l, 4 * l) : Vec3(0, 0, 0);
  EXPECT_NEAR(metered_exposure_ev(fb), 2.0, 0.15);
}

// One firefly does not decide: its zone is trimmed away with the brightest few percent.
TEST(Exposure, AFireflyIsTrimmed) {
  Framebuffer fb = grey(640, 360, 0.045f);
  fb.at(100, 100) = Vec3(1e5f, 1e5f, 1e5f);
  EXPECT_NEAR(metered_exposure_ev(fb), 2.0, 0.01);
}

// Nearly black images are not amplified without bound; empty or black ones keep 0.
TEST(Exposure, TheRangeIsBounded) {
  EXPECT_EQ(metered_exposure_ev(grey(32, 32, 1e-5f)), kMeterMaxStops);
  EXPECT_EQ(metered_exposure_ev(grey(32, 32, 1e9f)), -kMeterMaxStops);
  EXPECT_EQ(metered_exposure_ev(grey(32, 32, 0.0f)), 0.0f);
  EXPECT_EQ(metered_exposure_ev(Framebuffer()), 0.0f);
  Framebuffer nan = grey(8, 8, 0.045f);
  nan.at(0, 0) = Vec3(NAN, 0, 0);  // a non-finite pixel is not read
  EXPECT_TRUE(std::isfinite(metered_exposure_ev(nan)));
}

}  // namespace exposure_test
