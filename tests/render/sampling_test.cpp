// The warps' azimuth (render/shared/sampling.h's cos_sin_turns), shared by the CPU path
// tracer and the OpenCL kernel.
#include <gtest/gtest.h>

#include <cmath>

#include "render/shared/sampling.h"

namespace multiray {
namespace {

// Against double precision at 2^20 + 1 evenly spaced turns (every quarter-turn boundary,
// where the reduction switches quadrant, included) and at the largest float below 1: both
// values within 2.5e-7 (about four ulps of 1), and on the unit circle to the same.
TEST(CosSinTurns, MatchesTheTrueCosineAndSineOverAWholeTurn) {
  const int n = 1 << 20;
  double worst = 0.0, worst_norm = 0.0;
  auto check = [&](float turns) {
    const Vec2 cs = cos_sin_turns(turns);
    const double phi = 2.0 * M_PI * double(turns);
    worst = std::max(
        {worst, std::abs(double(cs.x) - std::cos(phi)), std::abs(double(cs.y) - std::sin(phi))});
    worst_norm = std::max(worst_norm, std::abs(double(cs.x) * cs.x + double(cs.y) * cs.y - 1.0));
  };
  for (int i = 0; i <= n; ++i) check(float(i) / float(n));
  check(std::nextafter(1.0f, 0.0f));
  EXPECT_LT(worst, 2.5e-7);
  EXPECT_LT(worst_norm, 5e-7);
}

// Each quadrant has the signs of its angle, and the quarter turns land on the axes
// exactly (a sample at a quarter turn leaves the frame's plane untouched).
TEST(CosSinTurns, QuarterTurnsAreExactAndQuadrantsKeepTheirSigns) {
  const Vec2 axes[5] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}};
  for (int q = 0; q <= 4; ++q) {
    const Vec2 cs = cos_sin_turns(0.25f * float(q));
    EXPECT_EQ(cs.x, axes[q].x) << q;
    EXPECT_EQ(cs.y, axes[q].y) << q;
  }
  for (int q = 0; q < 4; ++q) {
    const Vec2 cs = cos_sin_turns(0.25f * float(q) + 0.1f);  // 36 degrees into quadrant q
    EXPECT_EQ(cs.x > 0, q == 0 || q == 3) << q;
    EXPECT_EQ(cs.y > 0, q == 0 || q == 1) << q;
  }
}

}  // namespace
}  // namespace multiray
