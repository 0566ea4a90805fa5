// Leria et al.'s workload-ratio balancer: checks every `interval` frames, a ±`band`
// tolerance, the `slow` weighting, shuffled strips over all views.
#include <gtest/gtest.h>

#include "balance/balancer.h"
#include "balance/dlb.h"
#include "partition/shuffled_strips.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace dlb_test {

using namespace testing;

const FrameShape kShape{160, 90, 4, {}};

TEST(Dlb, RebalancesOnlyAtTheIntervalAndExactlyForSteadyTimings) {
  DlbBalancer b(2, 5, 0.1, 0.75);
  const auto run = simulate_run(b, kShape, constant({3, 1}), flat_cost(kShape), 12);
  for (int f = 0; f < 5; ++f) EXPECT_DOUBLE_EQ(planned(run[size_t(f)], 0), 0.5);
  for (int f = 5; f < 12; ++f) EXPECT_NEAR(planned(run[size_t(f)], 0), 0.75, 0.005);
  EXPECT_EQ(b.rebalances(), 1);  // at frame 10 the times are within the band
}

TEST(Dlb, NoRebalanceInsideTheBand) {
  DlbBalancer b(2, 2, 0.1, 0.75);
  simulate_run(b, kShape, constant({1.05, 1}), flat_cost(kShape), 10);  // 5% apart
  EXPECT_EQ(b.rebalances(), 0);
  DlbBalancer tight(2, 2, 0.01, 0.75);
  simulate_run(tight, kShape, constant({1.05, 1}), flat_cost(kShape), 10);
  EXPECT_GE(tight.rebalances(), 1);
}

TEST(Dlb, SlowWeightsTheLocalMeanOfSlowDevices) {
  // Device 1 is getting slower through the window: its latest time is above its mean.
  // slow = 1 uses the mean alone; smaller values lean towards the latest frame and take
  // more work away from it.
  auto last_ratio = [](double slow) {
    DlbBalancer b(2, 4, 0.1, slow);
    simulate_run(
        b, kShape,
        [](int f) {
          return devices_with_speeds({1, 1.0 / (1 + 0.5 * f)});
        },
        flat_cost(kShape), 4);
    return b.ratios()[1];
  };
  EXPECT_GT(last_ratio(1.0), last_ratio(0.75));
  EXPECT_GT(last_ratio(0.75), last_ratio(0.0));
}

TEST(Dlb, EveryViewGetsTheSameShareOfShuffledStrips) {
  DlbBalancer b(3, 1, 0.1, 0.75);
  const auto run = simulate_run(b, kShape, constant({2, 1, 1}), flat_cost(kShape), 3);
  const Plan& p = run.back().plan;
  const int64_t strip = (160 * 90) >> strip_bits_for(160 * 90, 32);
  for (int v = 0; v < 4; ++v) {
    int64_t px = 0;
    for (const WorkItem& it : p.assigned[0])
      if (it.view == v) px += it.rect.area();
    EXPECT_NEAR(double(px) / (160 * 90), 0.5, double(strip) / (160 * 90)) << v;
  }
}

TEST(Dlb, StripsPerFrameAreCappedOverAllViews) {
  // 320x180 views: 2^10 strips of 56 px each by the strip size; a 3x3 grid keeps them,
  // 9x9 is cut to 2^7 a view (81 x 128 = 10,368 <= 16,384), `items` moves the cap. A
  // strip becomes one to three rectangles (it may cross rows), hence the ranges.
  const auto strips_in = [](const std::string& spec, int views, size_t strips) {
    auto b = make_balancer(spec, 2);
    FrameShape shape;
    shape.width = 320, shape.height = 180, shape.views = views;
    const Plan p = b->plan(shape, 0);
    const size_t items = p.assigned[0].size() + p.assigned[1].size();
    EXPECT_GE(items, strips) << spec << " on " << views << " views";
    EXPECT_LE(items, 3 * strips) << spec << " on " << views << " views";
  };
  strips_in("dlb", 9, 9 * 1024);
  strips_in("dlb", 81, 81 * 128);
  strips_in("dlb:items=1000000", 81, 81 * 1024);
  strips_in("dlb:items=1", 81, 81);  // one strip a view at least
  strips_in("dlb:bits=3", 81, 81 * 8);
}

}  // namespace dlb_test
}  // namespace multiray::balance

namespace multiray::balance::dlb_baseline_test {

// Leria et al.'s baseline (their Algorithm 1) is equal ratios over the same shuffled strips:
// uniform:layout=strips must cut exactly dlb's strips, so that a comparison measures the
// balancing and not the strips' overhead.
TEST(Dlb, UniformStripsIsItsBaselineOnTheSameStrips) {
  const FrameShape shapes[] = {{1280, 720, 1, {}}, {320, 180, 9, {}}, {320, 180, 81, {}}};
  for (const std::string extra : {"", ":bits=6", ":strip=128", ":items=4096"})
    for (const FrameShape& shape : shapes) {
      const Plan dlb = make_balancer("dlb" + extra, 2)->plan(shape, 0);
      const Plan uniform = make_balancer("uniform:layout=strips" + extra, 2)->plan(shape, 0);
      ASSERT_EQ(dlb.assigned.size(), uniform.assigned.size());
      size_t items = 0;
      for (size_t d = 0; d < dlb.assigned.size(); ++d) {
        ASSERT_EQ(dlb.assigned[d].size(), uniform.assigned[d].size()) << extra;
        for (size_t k = 0; k < dlb.assigned[d].size(); ++k) {
          EXPECT_TRUE(dlb.assigned[d][k].rect == uniform.assigned[d][k].rect) << extra;
          EXPECT_EQ(dlb.assigned[d][k].view, uniform.assigned[d][k].view) << extra;
        }
        items += dlb.assigned[d].size();
      }
      EXPECT_GE(items, size_t(shape.views) * 2) << extra;  // strips, not two bands
    }
  // Without a layout, uniform keeps its two row bands (an extra lane in the reruns).
  const Plan rows = make_balancer("uniform", 2)->plan(FrameShape{320, 180, 1, {}}, 0);
  EXPECT_EQ(rows.assigned[0].size(), 1u);
  EXPECT_EQ(make_balancer("uniform:layout=strips", 2)->spec(),
            "uniform:layout=strips:bits=auto:strip=32:items=16384");
}

}  // namespace multiray::balance::dlb_baseline_test
