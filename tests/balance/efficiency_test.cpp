// Where a frame's time goes (balance/efficiency.h): the parts add up to the frame time for
// any input, known splits give known parts, and efficiency is above 1 only when the
// devices worked faster than when they were timed alone.
#include <gtest/gtest.h>

#include <random>

#include "balance/efficiency.h"

namespace multiray::balance {
namespace efficiency_test {

double sum(const Breakdown& b) {
  return b.ideal + b.balance_loss + b.overhead + b.stolen + b.host;
}

TEST(Efficiency, PartsAddUpToTheFrameForAnyInput) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.1, 100);
  for (int trial = 0; trial < 1000; ++trial) {
    std::vector<DeviceTiming> d(1 + trial % 5);
    double phase = 0;
    for (DeviceTiming& t : d) {
      t.alone_ms = u(rng), t.time_ms = u(rng), t.stolen_ms = u(rng) * (trial % 3 == 0);
      phase = std::max(phase, t.time_ms * (trial % 2 ? 1.0 : 0.9));  // sometimes t_i > W
    }
    const Breakdown b = break_down(d, phase, u(rng) * (trial % 4 == 0));
    ASSERT_TRUE(b.valid);
    EXPECT_NEAR(sum(b), b.total, 1e-9 * b.total) << trial;
    EXPECT_GE(b.balance_loss, 0) << trial;
    EXPECT_GE(b.stolen, 0) << trial;
    EXPECT_GE(b.host, 0) << trial;
    // Efficiency above 1 needs a negative overhead: the devices beat their alone times.
    if (b.efficiency() > 1) {
      EXPECT_LT(b.overhead, 0) << trial;
    }
  }
}

// Alone 10 and 30 ms: the ideal is 7.5 ms (4/30 + 1/30 of a frame per ms).
TEST(Efficiency, AnIdealSplitLosesNothing) {
  const Breakdown b = break_down({{10, 7.5, 0}, {30, 7.5, 0}}, 7.5, 0);
  EXPECT_DOUBLE_EQ(b.ideal, 7.5);
  EXPECT_NEAR(b.balance_loss, 0, 1e-12);
  EXPECT_NEAR(b.overhead, 0, 1e-12);
  EXPECT_DOUBLE_EQ(b.efficiency(), 1.0);
  EXPECT_EQ(above_one_explanation(b), "");
}

// Halves to each: the fast device (weight 3/4) finishes at 5 ms and waits 10 for the slow.
TEST(Efficiency, AnEvenSplitOfUnevenDevicesIsBalanceLoss) {
  const Breakdown b = break_down({{10, 5, 0}, {30, 15, 0}}, 15, 0);
  EXPECT_DOUBLE_EQ(b.balance_loss, 0.75 * 10);
  EXPECT_NEAR(b.overhead, 0, 1e-12);
  EXPECT_DOUBLE_EQ(b.efficiency(), 0.5);
}

TEST(Efficiency, StolenAndHostTimeAreTheirOwnParts) {
  // Both devices took 2 ms longer than ideal, 1.5 ms of it preempted; 1 ms of planning.
  const Breakdown b = break_down({{10, 9.5, 1.5}, {30, 9.5, 1.5}}, 9.5, 1);
  EXPECT_NEAR(b.stolen, 1.5, 1e-12);
  EXPECT_NEAR(b.overhead, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(b.host, 1);
  EXPECT_DOUBLE_EQ(b.total, 10.5);
  EXPECT_DOUBLE_EQ(b.efficiency(), 7.5 / 10.5);
  // Stolen time beyond a device's own time is not believed.
  EXPECT_NEAR(break_down({{10, 4, 9}}, 4, 0).stolen, 4, 1e-12);
}

TEST(Efficiency, AboveOneIsExplainedByDevicesBeatingTheirAloneTimes) {
  // Each device worked 20% faster than when it was timed alone.
  const Breakdown b = break_down({{10, 6, 0}, {30, 6, 0}}, 6, 0);
  EXPECT_GT(b.efficiency(), 1);
  EXPECT_NEAR(b.overhead, -1.5, 1e-12);
  const std::string why = above_one_explanation(b);
  EXPECT_NE(why.find("20.0% less than the ideal"), std::string::npos) << why;
}

TEST(Efficiency, ImpossibleInputsGiveNoBreakdown) {
  EXPECT_FALSE(break_down({}, 10, 0).valid);
  EXPECT_FALSE(break_down({{0, 5, 0}}, 10, 0).valid);
  EXPECT_FALSE(break_down({{10, 5, 0}}, 0, 0).valid);
  EXPECT_FALSE(break_down({{10, 5, 0}}, std::nan(""), 0).valid);
  EXPECT_EQ(break_down({{10, 5, 0}}, 0, 0).efficiency(), 0);
}

TEST(Efficiency, TheMeanOfBreakdownsStillAddsUp) {
  const Breakdown a = break_down({{10, 5, 0}, {30, 15, 0}}, 15, 1);
  const Breakdown b = break_down({{10, 9.5, 1.5}, {30, 9.5, 1.5}}, 9.5, 0);
  const Breakdown m = mean_breakdown({a, Breakdown{}, b});
  ASSERT_TRUE(m.valid);
  EXPECT_DOUBLE_EQ(m.total, (a.total + b.total) / 2);
  EXPECT_NEAR(sum(m), m.total, 1e-12);
  EXPECT_FALSE(mean_breakdown({Breakdown{}}).valid);
}

}  // namespace efficiency_test
}  // namespace multiray::balance
