// One definition of imbalance and deviation: over plain times and over a frame's reports
// (alive devices only), with unusable times left out.
#include <gtest/gtest.h>

#include <cmath>

#include "balance/stats.h"

namespace multiray::balance {
namespace stats_test {

using Times = std::vector<double>;

TEST(Stats, ImbalanceAndDeviationOfTimes) {
  // Mean 20: the slowest is 10 above it, the fastest 15 below.
  EXPECT_DOUBLE_EQ(imbalance(Times{30, 25, 5}), 0.5);
  EXPECT_DOUBLE_EQ(deviation(Times{30, 25, 5}), 0.75);
  // With two devices the two are the same number.
  EXPECT_DOUBLE_EQ(imbalance(Times{30, 10}), deviation(Times{30, 10}));
  EXPECT_EQ(imbalance(Times{7}), 0);
  EXPECT_EQ(imbalance(Times{}), 0);
  EXPECT_EQ(imbalance(Times{0, 0}), 0);
  EXPECT_DOUBLE_EQ(imbalance(Times{30, 10, NAN, -1, INFINITY}), 0.5);  // unusable ones left out
}

TEST(Stats, FrameReportsUseTheSameDefinitionOverAliveDevices) {
  FrameStats f;
  f.devices.resize(4);
  const double t[4] = {30, 25, 5, 1000};
  for (int i = 0; i < 4; ++i) f.devices[size_t(i)].time_ms = t[i];
  f.devices[3].alive = false;
  EXPECT_DOUBLE_EQ(imbalance(f), imbalance(Times{30, 25, 5}));
  EXPECT_DOUBLE_EQ(deviation(f), deviation(Times{30, 25, 5}));
}

}  // namespace stats_test
}  // namespace multiray::balance
