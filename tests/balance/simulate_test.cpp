// The simulator implements Plan's dispatch semantics exactly: own list in order, then
// batches from the shared queue, then stealing the last not-started item of the device
// with the most not-started work.
#include <gtest/gtest.h>

#include "balance/simulate.h"
#include "partition/coverage.h"

namespace multiray::balance {
namespace simulate_test {

const FrameShape kShape{10, 10, 1, {}};

WorkItem row(int y, int rows = 1) { return WorkItem{Rect{0, y, 10, y + rows}, 0}; }

std::vector<SimDevice> speeds(std::vector<double> s) {
  std::vector<SimDevice> d(s.size());
  for (size_t i = 0; i < s.size(); ++i) d[i].speed = s[i];
  return d;
}

TEST(Simulate, OwnItemsInOrderAndTimesFromCostAndSpeed) {
  Plan plan;
  plan.assigned = {{row(0, 5), row(5, 5)}, {}};
  plan.ratios = {1, 0};
  const FrameStats s = simulate(plan, kShape, speeds({2, 1}), uniform_cost(kShape, 1.0));
  ASSERT_EQ(s.devices[0].items.size(), 2u);
  EXPECT_EQ(s.devices[0].items[0].item, row(0, 5));
  EXPECT_DOUBLE_EQ(s.devices[0].items[0].time_ms, 25.0);  // 50 px at 1 ms / 2
  EXPECT_DOUBLE_EQ(s.devices[0].time_ms, 50.0);
  EXPECT_DOUBLE_EQ(s.devices[0].pixels, 100.0);
  EXPECT_DOUBLE_EQ(s.devices[1].time_ms, 0.0);  // no stealing: device 1 stays idle
}

TEST(Simulate, SharedQueueIsPulledInBatchesByWhoeverIsFree) {
  Plan plan;
  plan.assigned = {{}, {}};
  for (int y = 0; y < 10; ++y) plan.shared.push_back(row(y));
  plan.batch = 2;
  plan.ratios = {0.5, 0.5};
  const FrameStats s = simulate(plan, kShape, speeds({3, 1}), uniform_cost(kShape, 1.0));
  // Device 0 (3× faster) pulls rows 0–1, device 1 rows 2–3, device 0 rows 4–5 at t=6.67, …
  EXPECT_EQ(s.devices[1].items[0].item, row(2));
  EXPECT_EQ(s.devices[0].items[2].item, row(4));
  EXPECT_EQ(s.devices[0].items.size() + s.devices[1].items.size(), 10u);
  EXPECT_GT(s.devices[0].pixels, 2 * s.devices[1].pixels);
}

TEST(Simulate, StealsTheLastItemOfTheMostLoadedDevice) {
  Plan plan;
  plan.assigned = {{row(0), row(1), row(2), row(3), row(4), row(5)}, {row(6)}, {row(7, 3)}};
  plan.steal = true;
  plan.ratios = {0.6, 0.1, 0.3};
  const FrameStats s = simulate(plan, kShape, speeds({1, 1, 1}), uniform_cost(kShape, 1.0));
  // At t=10 device 1 is free: device 0 has 5 rows left, device 2 none (its one item runs).
  ASSERT_GE(s.devices[1].items.size(), 2u);
  EXPECT_EQ(s.devices[1].items[1].item, row(5));
  std::vector<WorkItem> all;
  for (const auto& d : s.devices)
    for (const auto& r : d.items) all.push_back(r.item);
  EXPECT_EQ(coverage_error(all, 10, 10, 1), "");
  EXPECT_DOUBLE_EQ(s.devices[0].time_ms, 40.0);  // rows 0–3; 4 and 5 were stolen
}

TEST(Simulate, DeadDevicesWorkIsStolenOrLeft) {
  Plan plan;
  plan.assigned = {{row(0, 5)}, {row(5, 5)}};
  plan.ratios = {0.5, 0.5};
  std::vector<SimDevice> d = speeds({1, 1});
  d[1].alive = false;
  FrameStats s = simulate(plan, kShape, d, uniform_cost(kShape, 1.0));
  EXPECT_FALSE(s.devices[1].alive);
  EXPECT_DOUBLE_EQ(s.devices[0].pixels, 50.0);
  plan.steal = true;
  s = simulate(plan, kShape, d, uniform_cost(kShape, 1.0));
  EXPECT_DOUBLE_EQ(s.devices[0].pixels, 100.0);
}

TEST(Simulate, MidFrameSpeedChangeSplitsTheItem) {
  Plan plan;
  plan.assigned = {{row(0, 10)}};
  plan.ratios = {1};
  std::vector<SimDevice> d = speeds({1});
  d[0].change_at_ms = 40;
  d[0].speed_after = 0.5;
  const FrameStats s = simulate(plan, kShape, d, uniform_cost(kShape, 1.0));
  EXPECT_DOUBLE_EQ(s.devices[0].time_ms, 40.0 + 60.0 / 0.5);
}

TEST(Simulate, WeightsCountSamplesAndNoiseIsSeeded) {
  FrameShape shape = kShape;
  shape.pixel_weight.assign(100, 2.0f);
  Plan plan;
  plan.assigned = {{row(0, 10)}};
  plan.ratios = {1};
  std::vector<SimDevice> d = speeds({1});
  d[0].item_noise = 0.1;
  const FrameStats a = simulate(plan, shape, d, uniform_cost(shape, 1.0), 3, 42);
  const FrameStats b = simulate(plan, shape, d, uniform_cost(shape, 1.0), 3, 42);
  EXPECT_DOUBLE_EQ(a.devices[0].samples, 200.0);
  EXPECT_DOUBLE_EQ(a.devices[0].time_ms, b.devices[0].time_ms);
  EXPECT_NEAR(a.devices[0].time_ms, 200.0, 20.0 + 1e-9);
}

TEST(Simulate, FrameOverheadDelaysTheFirstItem) {
  Plan plan;
  plan.assigned = {{row(0, 5), row(5, 5)}, {}};
  plan.ratios = {1, 0};
  std::vector<SimDevice> d = speeds({2, 1});
  d[0].frame_overhead_ms = 3;
  const FrameStats s = simulate(plan, kShape, d, uniform_cost(kShape, 1.0));
  EXPECT_DOUBLE_EQ(s.devices[0].items[0].time_ms, 25.0);  // not in any item
  EXPECT_DOUBLE_EQ(s.devices[0].time_ms, 53.0);           // but in the device's frame
}

TEST(Simulate, ContentionSlowsItemsStartedWhileOthersWork) {
  // Device 0: two rows; device 1: eight. While both work each runs 1.5x slower; device 1's
  // items started after device 0 ran dry run at full speed.
  Plan plan;
  plan.assigned = {{row(0), row(1)},
                   {row(2), row(3), row(4), row(5), row(6), row(7), row(8), row(9)}};
  plan.ratios = {0.2, 0.8};
  std::vector<SimDevice> d = speeds({1, 1});
  for (SimDevice& x : d) x.contention = 0.5;
  const FrameStats s = simulate(plan, kShape, d, uniform_cost(kShape, 1.0));
  EXPECT_DOUBLE_EQ(s.devices[0].items[0].time_ms, 15.0);  // 10 ms × 1.5
  EXPECT_DOUBLE_EQ(s.devices[0].time_ms, 30.0);
  EXPECT_DOUBLE_EQ(s.devices[1].items[1].time_ms, 15.0);  // started at 15: both at work
  EXPECT_DOUBLE_EQ(s.devices[1].items[2].time_ms, 10.0);  // started at 30: alone
  EXPECT_DOUBLE_EQ(s.devices[1].time_ms, 30.0 + 6 * 10.0);
}

TEST(Simulate, RejectsMismatchedDevices) {
  Plan plan;
  plan.assigned = {{row(0, 10)}};
  EXPECT_THROW(simulate(plan, kShape, speeds({1, 1}), uniform_cost(kShape, 1.0)),
               std::invalid_argument);
  EXPECT_THROW(simulate(plan, kShape, speeds({0}), uniform_cost(kShape, 1.0)),
               std::invalid_argument);
}

}  // namespace simulate_test
}  // namespace multiray::balance
