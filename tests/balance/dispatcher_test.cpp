// The Dispatcher: the one executor of a Plan. Its rules are checked directly, from
// several threads, and through the simulator.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <thread>

#include "balance/balancer.h"
#include "balance/dispatcher.h"
#include "balance/simulate.h"
#include "partition/coverage.h"

namespace multiray::balance {
namespace dispatcher_test {

WorkItem row(int y, int width = 10) { return WorkItem{Rect{0, y, width, y + 1}, 0}; }

Plan two_lists_and_queue() {
  Plan p;
  p.assigned = {{row(0), row(1), row(2)}, {row(3)}};
  p.shared = {row(4), row(5), row(6), row(7), row(8)};
  p.batch = 2;
  p.steal = true;
  p.ratios = {0.5, 0.5};
  return p;
}

const FrameShape kShape{10, 9, 1, {}};

TEST(Dispatcher, OwnListThenSharedInBatchesThenSteals) {
  Dispatcher d(two_lists_and_queue(), kShape);
  uint32_t id;
  ASSERT_TRUE(d.next(1, id));
  EXPECT_EQ(id, 3u);  // its own item first
  ASSERT_TRUE(d.next(1, id));
  EXPECT_EQ(id, 4u);  // then a batch of two from the shared queue: 4, 5
  EXPECT_EQ(d.pending(1), std::vector<uint32_t>{5});
  ASSERT_TRUE(d.next(1, id));
  EXPECT_EQ(id, 5u);
  std::vector<uint32_t> got;
  EXPECT_EQ(d.next(1, 10, got), 6u);  // 6, 7, 8, then steals 2, 1, 0 from device 0's back
  EXPECT_EQ(got, (std::vector<uint32_t>{6, 7, 8, 2, 1, 0}));
  EXPECT_EQ(d.stolen(), 3);
  EXPECT_FALSE(d.next(0, id));
  for (uint32_t i = 0; i < 9; ++i) EXPECT_EQ(d.taken_by(i), 1) << i;
}

TEST(Dispatcher, PrefetchedItemsStayStealableStartedOnesDoNot) {
  Plan p = two_lists_and_queue();
  p.assigned[0].clear();
  p.assigned[1].clear();
  Dispatcher d(p, kShape);
  // Only the shared queue is left: its rows 4..8 are items 0..4.
  EXPECT_EQ(d.prefetch(1, 3), 3u);  // 0, 1, 2 now device 1's, not started
  EXPECT_EQ(d.pending(1), (std::vector<uint32_t>{0, 1, 2}));
  uint32_t id;
  ASSERT_TRUE(d.next(1, id));  // starts 0
  EXPECT_EQ(id, 0u);
  // Device 0 takes the rest of the queue in a batch, then steals 2 and 1 (not started).
  std::vector<uint32_t> got;
  d.next(0, 10, got);
  EXPECT_EQ(got, (std::vector<uint32_t>{3, 4, 2, 1}));
  EXPECT_EQ(d.taken_by(0), 1);
  EXPECT_EQ(d.taken_by(2), 0);
  EXPECT_FALSE(d.next(1, id));
}

TEST(Dispatcher, WithoutStealingAnIdleDeviceStops) {
  Plan p = two_lists_and_queue();
  p.shared.clear();
  p.steal = false;
  Dispatcher d(p, kShape);
  uint32_t id;
  ASSERT_TRUE(d.next(1, id));
  EXPECT_FALSE(d.next(1, id));
  EXPECT_EQ(d.take_remaining(0), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_FALSE(d.next(0, id));
}

TEST(Dispatcher, StealsFromTheMostWeightedWork) {
  FrameShape shape = kShape;
  shape.pixel_weight.assign(90, 1.0f);
  for (int x = 0; x < 10; ++x) shape.pixel_weight[size_t(3 * 10 + x)] = 100.0f;  // row 3
  Plan p;
  p.assigned = {{row(0), row(1), row(2)}, {row(3)}, {}};
  p.steal = true;
  Dispatcher d(p, shape);
  uint32_t id;
  ASSERT_TRUE(d.next(2, id));
  EXPECT_EQ(id, 3u);  // device 1's one row weighs more than device 0's three
}

TEST(Dispatcher, ManyThreadsTakeEveryItemExactlyOnce) {
  const FrameShape shape{97, 61, 2, {}};
  Plan p;
  p.assigned.resize(4);
  for (int v = 0; v < 2; ++v)
    for (int y = 0; y < shape.height; ++y) {
      const WorkItem it{Rect{0, y, shape.width, y + 1}, v};
      if (y % 3 == 0)
        p.shared.push_back(it);
      else
        p.assigned[size_t(y % 4)].push_back(it);
    }
  p.steal = true;
  p.batch = 3;
  p.ratios.assign(4, 0.25);
  Dispatcher d(p, shape);
  std::vector<std::vector<uint32_t>> taken(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (uint32_t id; d.next(t, id);) taken[size_t(t)].push_back(id);
    });
  for (auto& t : threads) t.join();
  std::vector<WorkItem> all;
  for (int t = 0; t < 4; ++t)
    for (uint32_t id : taken[size_t(t)]) {
      EXPECT_EQ(d.taken_by(id), t);
      all.push_back(d.items()[id]);
    }
  EXPECT_EQ(all.size(), d.items().size());
  EXPECT_EQ(coverage_error(all, shape.width, shape.height, shape.views), "");
}

TEST(Dispatcher, SimulatorReportsTheDispatcherNumbering) {
  const Plan p = two_lists_and_queue();
  const auto stats = simulate(p, kShape, {SimDevice{}, SimDevice{}}, uniform_cost(kShape, 1.0));
  const std::vector<WorkItem> all = p.all_items();
  size_t n = 0;
  for (const auto& dev : stats.devices)
    for (const ItemReport& r : dev.items) {
      EXPECT_EQ(all[r.id], r.item);
      ++n;
    }
  EXPECT_EQ(n, all.size());
}

// Seo's strategy I: the queue asks workers behind a link for the paper's one tile at a
// time on a ready report unless told `pipeline=deep` (ours); the Dispatcher passes it on.
TEST(Dispatcher, TheQueueAsksForThePapersPipelineByDefault) {
  const auto paper = make_balancer("queue:tile=4", 2)->plan(kShape, 0);
  const auto deep = make_balancer("queue:tile=4:pipeline=deep", 2)->plan(kShape, 0);
  EXPECT_TRUE(paper.pull_on_ready);
  EXPECT_FALSE(deep.pull_on_ready);
  EXPECT_TRUE(Dispatcher(paper, kShape).pull_on_ready());
  EXPECT_FALSE(Dispatcher(deep, kShape).pull_on_ready());
  EXPECT_FALSE(make_balancer("ospray-dynamic", 2)->plan(kShape, 0).pull_on_ready);
  EXPECT_THROW(make_balancer("queue:pipeline=shallow", 2), std::invalid_argument);
}

}  // namespace dispatcher_test
}  // namespace multiray::balance
