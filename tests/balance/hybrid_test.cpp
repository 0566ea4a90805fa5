// The hybrid balancer: one-frame convergence, stealing that absorbs a slowdown inside a
// frame, speeds measured on the work really done, interleaved contiguous pieces with a
// shrinking tail, no drift of its estimates over long runs, and each device's fixed cost
// per item learnt and planned with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "balance/hybrid.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace hybrid_test {

using namespace testing;

const FrameShape kShape{640, 360, 1, {}};

TEST(Hybrid, BalancedFromTheSecondFrameOnUnevenCost) {
  // Frame 0 is split evenly; stealing already measures the speeds on it.
  HybridBalancer pair(2);
  const auto two = simulate_run(pair, kShape, constant({3, 1}), uneven_cost(kShape), 10);
  for (int f = 1; f < 10; ++f) EXPECT_LT(imbalance(two[size_t(f)].stats), 0.02) << f;
  // Five unequal devices: the row costs take a few frames to learn.
  HybridBalancer five(5);
  const auto run =
      simulate_run(five, kShape, constant({4, 1, 2, 0.5, 3}), uneven_cost(kShape), 30);
  for (int f = 1; f < 30; ++f) EXPECT_LT(imbalance(run[size_t(f)].stats), 0.05) << f;
  EXPECT_LT(mean_imbalance(run, 1, 10), 0.025);
  EXPECT_LT(mean_imbalance(run, 10, 30), 0.01);
}

TEST(Hybrid, StealingAbsorbsASlowdownInsideTheFrame) {
  // Device 0 falls from speed 3 to 1 at 40% of frame 10. Without stealing that frame is
  // ~40% imbalanced; with it, the tail chunks move to device 1.
  auto devices = [](int f) {
    auto d = devices_with_speeds({3, 1});
    if (f == 10) d[0].change_at_ms = 23, d[0].speed_after = 1;
    if (f > 10) d[0].speed = 1;
    return d;
  };
  HybridBalancer with(2);
  HybridBalancer::Options no_steal;
  no_steal.steal = false;
  HybridBalancer without(2, no_steal);
  const auto a = simulate_run(with, kShape, devices, flat_cost(kShape), 13);
  const auto b = simulate_run(without, kShape, devices, flat_cost(kShape), 13);
  EXPECT_LT(imbalance(a[10].stats), 0.06);
  EXPECT_GT(imbalance(b[10].stats), 0.3);
  // Frame 11 plans with the speed averaged over frame 10 (stealing absorbs the rest);
  // frame 12 with the new one.
  EXPECT_LT(imbalance(a[11].stats), 0.05);
  // (In model cost units, which frame 10's slowdown distorted by a few percent: the
  // measured speeds of frame 11 are off by up to 5%, which detect=noise takes at once on
  // these noiseless devices; 0.474 here, 0.481 with detect=fixed.)
  EXPECT_NEAR(planned(a[12], 0), 0.5, 0.03);
  EXPECT_LT(imbalance(a[12].stats), 0.02);
}

TEST(Hybrid, SpeedsCountStolenWork) {
  // Frame 0 is planned evenly; stealing moves work to the faster device, and its speed
  // must be measured on all it rendered, not on its planned half.
  HybridBalancer b(2);
  const auto run = simulate_run(b, kShape, constant({3, 1}), flat_cost(kShape), 1);
  EXPECT_GT(run[0].stats.devices[0].pixels, 0.7 * 640 * 360);
  ASSERT_GT(b.speeds()[1], 0);
  EXPECT_NEAR(b.speeds()[0] / b.speeds()[1], 3.0, 0.1);
}

// Device i's items as contiguous runs of flat pixel positions.
int contiguous_runs(const std::vector<WorkItem>& items, const FrameShape& s) {
  std::vector<std::pair<int64_t, int64_t>> ranges;
  for (const WorkItem& it : items) {
    const int64_t base = int64_t(it.view) * s.height * s.width;
    ranges.push_back({base + int64_t(it.rect.y0) * s.width + it.rect.x0,
                      base + int64_t(it.rect.y1 - 1) * s.width + it.rect.x1});
  }
  std::sort(ranges.begin(), ranges.end());
  int runs = 0;
  for (size_t k = 0; k < ranges.size(); ++k)
    if (k == 0 || ranges[k].first != ranges[k - 1].second) ++runs;
  return runs;
}

TEST(Hybrid, InterleavedPiecesWithAShrinkingTail) {
  HybridBalancer b(3);
  const auto run = simulate_run(b, kShape, constant({2, 1, 1}), flat_cost(kShape), 3);
  const Plan& p = run.back().plan;
  EXPECT_TRUE(p.steal);
  for (int i = 0; i < 3; ++i) {
    const auto& items = p.assigned[size_t(i)];
    EXPECT_LE(contiguous_runs(items, kShape), 8) << i;  // one piece per band at most
    EXPECT_GE(contiguous_runs(items, kShape), 4) << i;  // spread over the frame
    // The last item (stolen first) is much smaller than a piece: a piece is 1/8 of the
    // device's share.
    int64_t share = 0;
    for (const WorkItem& it : items) share += it.rect.area();
    EXPECT_LT(items.back().rect.area() * 8 * 4, share) << i;
  }
}

TEST(Hybrid, EstimatesDoNotDriftWithMovingCost) {
  // A cost hotspot drifting up and down the frame for 300 frames, 5 unequal devices.
  // (A single contiguous range per device lets the speed estimates wander; the
  // interleaved bands keep them on the true speeds.)
  const std::vector<double> speeds = {4, 1, 2, 0.5, 3};
  const FrameShape shape{320, 180, 1, {}};
  HybridBalancer b(5);
  double efficiency = 0;
  for (int f = 0; f < 300; ++f) {
    const double centre = 90 + 72 * std::sin(f * 0.02);
    const CostFn cost = pixel_cost(shape, [centre](int, int x, int y) {
      return 1e-3 * (1 + 8 * std::exp(-std::pow((y - centre) / 20.0, 2)) * (x > 160 ? 1.5 : 0.5));
    });
    const Plan p = b.plan(shape, f);
    const FrameStats s = simulate(p, shape, devices_with_speeds(speeds, 0.03), cost, f, 3);
    b.update(s);
    if (f >= 10) efficiency += cost(WorkItem{Rect{0, 0, 320, 180}, 0}) / 10.5 / frame_time_ms(s);
    if (f >= 250) {
      for (int i = 0; i < 5; ++i) EXPECT_NEAR(p.ratios[size_t(i)], speeds[size_t(i)] / 10.5, 0.02);
    }
  }
  EXPECT_GT(efficiency / 290, 0.95);
}

TEST(Hybrid, SplitsIrregularSamplesByWork) {
  // Adaptive sampling: a moving diagonal edge band at 5 spp, 1 spp elsewhere; 4 devices.
  FrameShape shape{320, 180, 1, {}};
  HybridBalancer b(4);
  double dev = 0;
  for (int f = 0; f < 40; ++f) {
    shape.pixel_weight.assign(size_t(320 * 180), 1.0f);
    for (int y = 0; y < 180; ++y)
      for (int x = 0; x < 320; ++x)
        if (std::abs(x - 160 - 100 * std::sin(f * 0.1) - 0.5 * y) < 20)
          shape.pixel_weight[size_t(y * 320 + x)] = 5;
    const Plan p = b.plan(shape, f);
    ASSERT_EQ(check_plan(p, shape, 4), "");
    const FrameStats s = simulate(p, shape, devices_with_speeds({4, 3, 2, 1}, 0.01),
                                  uniform_cost(shape, 1e-3), f, 5);
    b.update(s);
    if (f >= 5) dev += deviation(s);
  }
  EXPECT_LT(dev / 35, 0.02);
}

TEST(Hybrid, MultiviewLightField) {
  const FrameShape shape{96, 54, 9, {}};  // 3×3 views
  HybridBalancer b(2);
  const CostFn cost =
      pixel_cost(shape, [](int v, int, int y) { return 1e-3 * (1 + v % 3 + (y > 30 ? 4 : 0)); });
  const auto run = simulate_run(b, shape, constant({3, 1}, 0.02), cost, 20);
  EXPECT_LT(mean_imbalance(run, 2, 20), 0.02);
}

TEST(Hybrid, NewShapeResetsTheCostModel) {
  HybridBalancer b(2);
  simulate_run(b, kShape, constant({3, 1}), uneven_cost(kShape), 5);
  const FrameShape other{100, 50, 2, {}};
  const auto run = simulate_run(b, other, constant({3, 1}), flat_cost(other), 3);
  EXPECT_EQ(b.row_cost().size(), 100u);
  EXPECT_LT(imbalance(run[0].stats), 0.03);  // speeds carry over
}

// A device that pays a fixed time for every item it takes (a kernel launch and read-back,
// say), as the PoCL device measured 0.1–0.14 ms an item next to a CPU core's 0.01.
std::vector<SimDevice> with_fixed_cost(const std::vector<double>& speeds,
                                       const std::vector<double>& fixed_ms, double frame_noise,
                                       double item_noise) {
  auto d = devices_with_speeds(speeds, frame_noise);
  for (size_t i = 0; i < d.size(); ++i) {
    d[i].item_overhead_ms = fixed_ms[i];
    d[i].item_noise = item_noise;
  }
  return d;
}

TEST(Hybrid, LearnsEachDevicesFixedCostPerItem) {
  HybridBalancer b(2);
  simulate_run(
      b, kShape,
      [](int) {
        return with_fixed_cost({3, 1}, {0, 0.3}, 0.02, 0.05);
      },
      uneven_cost(kShape), 30, 7);
  // Two standard errors below the fits: on the safe side of 0.3, never above it.
  EXPECT_GT(b.overheads()[1], 0.15);
  EXPECT_LT(b.overheads()[1], 0.3);
  EXPECT_LT(b.overheads()[0], 0.02);
  // Speeds net of the fixed costs.
  EXPECT_NEAR(b.speeds()[0] / b.speeds()[1], 3.0, 0.3);
}

TEST(Hybrid, FewerLargerChunksForADeviceWithAFixedCost) {
  HybridBalancer::Options off;
  off.overhead = 0;
  HybridBalancer with(2), without(2, off);
  auto devices = [](int) { return with_fixed_cost({3, 1}, {0.01, 0.3}, 0.02, 0.05); };
  const auto a = simulate_run(with, kShape, devices, uneven_cost(kShape), 20, 3);
  const auto b = simulate_run(without, kShape, devices, uneven_cost(kShape), 20, 3);
  const Plan& p = a.back().plan;
  const Plan& q = b.back().plan;
  // Device 1: chunks of at least 9× its fixed cost, cuts moved to row boundaries.
  EXPECT_LT(2 * p.assigned[1].size(), q.assigned[1].size());
  EXPECT_LE(p.assigned[1].size(), 16u);
  // The split counts the fixed costs: device 1 gets less than its speed's share.
  EXPECT_LT(planned(a.back(), 1), 0.25);
  EXPECT_LT(mean_imbalance(a, 5, 20), 0.02);
}

// Efficiency (ideal frame time at the nominal speeds, without fixed costs, over the frame
// time) of `spec` on a CPU + PoCL-like pair: 2.5 : 1, fixed costs 0.01 and 0.2 ms an item,
// ±5% per frame and ±10% per item, a cost hotspot sweeping up and down the frame; frames
// 10–59 of a 640×360 frame of ~57 ms, mean over three seeds.
double fixed_cost_pair_efficiency(const std::string& spec) {
  static const std::vector<CostFn> costs = [] {
    std::vector<CostFn> c;
    for (int f = 0; f < 60; ++f) {
      const double centre = 180 + 140 * std::sin(f * 0.05);
      c.push_back(pixel_cost(kShape, [centre](int, int x, int y) {
        return 4e-4 * (1 + 6 * std::exp(-std::pow((y - centre) / 40.0, 2)) * (0.5 + x / 640.0));
      }));
    }
    return c;
  }();
  const auto devices = with_fixed_cost({2.5, 1}, {0.01, 0.2}, 0.05, 0.1);
  double sum = 0;
  int n = 0;
  for (uint64_t seed : {1, 2, 3}) {
    const auto b = make_balancer(spec, 2);
    for (int f = 0; f < 60; ++f) {
      const CostFn& cost = costs[size_t(f)];
      const SimFrame s = simulate_linked(b->plan(kShape, f), kShape, devices, cost, {}, f, seed);
      b->update(s.stats);
      if (f >= 10) sum += cost(WorkItem{Rect{0, 0, 640, 360}, 0}) / 3.5 / s.frame_ms, ++n;
    }
  }
  return sum / n;
}

TEST(Hybrid, BeatsEveryBalancerWhenItemsCostAFixedTime) {
  // Measured: hybrid 0.974 (14 items a frame on device 1); hybrid:overhead=0, the hybrid
  // before the fixed-cost model, 0.955 (36 items); queue 0.957, semi-static 0.930,
  // equalizer 0.944, ospray-dynamic 0.890, the rest below 0.8.
  const double hybrid = fixed_cost_pair_efficiency("hybrid");
  EXPECT_GT(hybrid, 0.97);
  for (const std::string other :
       {"hybrid:overhead=0", "queue", "semi-static", "dlb", "static", "uniform", "cycles",
        "equalizer", "ospray-static", "ospray-dynamic"})
    EXPECT_GT(hybrid, fixed_cost_pair_efficiency(other) + 0.005) << other;
}

TEST(Hybrid, WithoutFixedCostsPlansAsBefore) {
  // No fixed cost to find: the model stays at 0 and the plans are the old ones, item for
  // item (speed noise only; the row-cost model errs at first, which must not pass for a
  // fixed cost).
  HybridBalancer::Options off;
  off.overhead = 0;
  HybridBalancer with(2), without(2, off);
  const auto a = simulate_run(with, kShape, constant({3, 1}, 0.05), uneven_cost(kShape), 30, 5);
  const auto b = simulate_run(without, kShape, constant({3, 1}, 0.05), uneven_cost(kShape), 30, 5);
  for (size_t f = 0; f < a.size(); ++f) {
    ASSERT_EQ(a[f].plan.assigned, b[f].plan.assigned) << f;
    EXPECT_EQ(a[f].plan.ratios, b[f].plan.ratios) << f;
  }
  EXPECT_EQ(with.overheads(), std::vector<double>(2, 0.0));
}

TEST(Hybrid, ASlowdownInsideTheFrameIsNoFixedCost) {
  // Device 0 falls from 3 to 1 at 40% of frame 10: its last (small) items are slow, as a
  // fixed cost would make them.
  auto devices = [](int f) {
    auto d = devices_with_speeds({3, 1});
    if (f == 10) d[0].change_at_ms = 23, d[0].speed_after = 1;
    if (f > 10) d[0].speed = 1;
    return d;
  };
  HybridBalancer b(2);
  simulate_run(b, kShape, devices, flat_cost(kShape), 13);
  EXPECT_EQ(b.overheads()[0], 0.0);
}

TEST(Hybrid, FixedCostFitSurvivesGarbage) {
  // detect=fixed: the fixed-cost evidence of this pair comes and goes (o_1 falls from
  // ~0.25 to 0 and back every 10–20 frames, in either mode: with few large chunks of
  // similar size no fit is possible and the evidence fades), and the noise model shifts
  // that cycle's phase, which the comparison with `before` below depends on.
  HybridBalancer::Options fixed;
  fixed.detect_noise = false;
  HybridBalancer b(2, fixed);
  const auto devices = with_fixed_cost({3, 1}, {0.01, 0.3}, 0.02, 0.05);
  simulate_run(
      b, kShape, [&](int) { return devices; }, uneven_cost(kShape), 10, 1);
  const std::vector<double> before = b.overheads();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 6; ++k) {
    FrameStats s = simulate(b.plan(kShape, 10 + k), kShape, devices, uneven_cost(kShape), 10 + k);
    // Some item times unusable, some absurd, one device's all identical in size.
    auto& items = s.devices[size_t(k % 2)].items;
    for (size_t j = 0; j < items.size(); j += 2)
      items[j].time_ms = std::vector<double>{nan, -1, inf, 0, 1e9, 1e-9}[size_t(k)];
    b.update(s);
    for (int i = 0; i < 2; ++i) {
      EXPECT_TRUE(std::isfinite(b.overheads()[size_t(i)])) << k;
      EXPECT_GE(b.overheads()[size_t(i)], 0) << k;
      EXPECT_LT(b.overheads()[size_t(i)], 0.5 * s.devices[size_t(i)].time_ms) << k;
    }
    const Plan p = b.plan(kShape, 20 + k);
    ASSERT_EQ(check_plan(p, kShape, 2), "") << k;
    for (double r : p.ratios) EXPECT_TRUE(std::isfinite(r) && r > 0) << k;
  }
  // Clean frames bring the estimate back.
  simulate_run(
      b, kShape, [&](int) { return devices; }, uneven_cost(kShape), 20, 2);
  EXPECT_NEAR(b.overheads()[1], before[1], 0.1);
}

}  // namespace hybrid_test
}  // namespace multiray::balance
