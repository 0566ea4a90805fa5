// The simulator's emulated links (Seo et al. 2022, Fig. 6): latency on every message,
// round trips for pulls and steals, results crossing a shared master link in turn.
#include <gtest/gtest.h>

#include "balance/simulate.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace link_test {

const FrameShape kShape{64, 32, 1, {}};

TEST(Link, StaticPlanPaysOneLatencyEachWay) {
  auto b = make_balancer("uniform", 2);
  const Plan p = b->plan(kShape, 0);
  SimLink link;
  link.latency_ms = 3;
  const auto f = simulate_linked(p, kShape, testing::devices_with_speeds({1, 1}),
                                 uniform_cost(kShape, 0.01), link);
  // Each device renders half the frame (1024 px at 0.01 ms) after the start message.
  EXPECT_DOUBLE_EQ(f.stats.devices[0].time_ms, 3 + 10.24);
  EXPECT_DOUBLE_EQ(f.frame_ms, 3 + 10.24 + 3);
  // Without a link nothing changes from simulate().
  const FrameStats plain =
      simulate(p, kShape, testing::devices_with_speeds({1, 1}), uniform_cost(kShape, 0.01));
  EXPECT_DOUBLE_EQ(plain.devices[0].time_ms, 10.24);
}

TEST(Link, EveryPullFromTheQueueIsARoundTrip) {
  auto b = make_balancer("queue:tile=16", 1);  // 8 tiles of 16x16 on one device
  SimLink link;
  link.latency_ms = 1;
  const auto f = simulate_linked(b->plan(kShape, 0), kShape, testing::devices_with_speeds({1}),
                                 uniform_cost(kShape, 0.01), link);
  EXPECT_EQ(f.stats.devices[0].items.size(), 8u);
  EXPECT_NEAR(f.stats.devices[0].time_ms, 1 + 8 * (2 + 2.56), 1e-9);
  // Results go out as tiles finish; the last arrives one latency after the device ends.
  EXPECT_NEAR(f.frame_ms, f.stats.devices[0].time_ms + 1, 1e-9);
}

TEST(Link, SharedMasterLinkCarriesResultsInTurn) {
  auto b = make_balancer("uniform", 2);
  const Plan p = b->plan(kShape, 0);
  SimLink link;
  link.mbit_per_s = 8e-3;  // 1 byte per ms: each half frame (1024 px x 4 bytes) takes 4096 ms
  const auto devices = testing::devices_with_speeds({1, 1});
  const auto shared = simulate_linked(p, kShape, devices, uniform_cost(kShape, 0.01), link);
  link.shared_master = false;
  const auto own = simulate_linked(p, kShape, devices, uniform_cost(kShape, 0.01), link);
  EXPECT_NEAR(own.frame_ms, 10.24 + 4096, 1e-6);
  EXPECT_NEAR(shared.frame_ms, 10.24 + 2 * 4096, 1e-6);
}

TEST(Link, PresetsAreTheIssuesFigures) {
  EXPECT_EQ(SimLink::lan().latency_ms, 0.1);
  EXPECT_EQ(SimLink::lan().mbit_per_s, 10000);
  EXPECT_EQ(SimLink::wifi().latency_ms, 5.0);
  EXPECT_EQ(SimLink::wifi().mbit_per_s, 200);
}

}  // namespace link_test
}  // namespace multiray::balance
