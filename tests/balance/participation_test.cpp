// The participation rule (balance/participation.h): the fit of a device's fixed cost per
// frame, the choice of the devices that take part, and hybrid on the simulator leaving out
// a device whose fixed cost outlasts the frame (it then costs nothing), probing it, and
// taking it back once it pays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "balance/hybrid.h"
#include "balance/participation.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace participation_test {

TEST(DeviceCostFit, RecoversTheFixedCostAndTheSpeed) {
  // t = 75 + n / 0.5, with a deterministic ±1 ms wobble.
  DeviceCostFit fit;
  const double works[] = {1000, 200, 50, 400, 20, 700, 90, 300};
  int k = 0;
  for (double n : works) fit.add(n, 75 + n / 0.5 + ((k++ % 2) ? 1.0 : -1.0));
  const DeviceCostModel m = fit.model();
  ASSERT_TRUE(m.determined);
  EXPECT_NEAR(m.fixed_ms, 75, 2);
  EXPECT_NEAR(m.speed, 0.5, 0.01);
  EXPECT_GT(m.fixed_sigma, 0);
  EXPECT_LT(m.fixed_sigma, 2);
}

TEST(DeviceCostFit, EqualWorkDeterminesNoFixedCost) {
  // A device that always renders the same share: intercept and slope cannot be told apart.
  DeviceCostFit fit;
  for (int f = 0; f < 20; ++f) fit.add(100, 40 + (f % 3));
  const DeviceCostModel m = fit.model();
  EXPECT_FALSE(m.determined);
  EXPECT_EQ(m.fixed_ms, 0);
  EXPECT_NEAR(m.speed, 100.0 / 41.0, 0.05);  // its mean speed
  DeviceCostFit two;                         // two frames are not enough either
  two.add(100, 50), two.add(10, 30);
  EXPECT_FALSE(two.model().determined);
}

TEST(DeviceCostFit, GarbageTeachesNothing) {
  DeviceCostFit fit;
  for (double bad :
       {-5.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    fit.add(bad, 10), fit.add(10, bad);
  }
  fit.add(10, 0.0);
  EXPECT_EQ(fit.frames(), 0);
  EXPECT_EQ(fit.model().speed, 0);
}

DeviceCostModel model(double speed, double fixed_ms, double sigma = 0) {
  return DeviceCostModel{speed, fixed_ms, sigma, true};
}

TEST(Participation, ADeviceWhoseFixedCostOutlastsTheFrameIsLeftOut) {
  // A core (44 ms for 44 units) and a device 14x slower with 75 ms fixed per frame.
  const std::vector<DeviceCostModel> m = {model(1, 0), model(1.0 / 14, 75)};
  const std::vector<bool> both = {true, true};
  EXPECT_EQ(choose_participants(m, both, 44, 0.03), (std::vector<bool>{true, false}));
  EXPECT_NEAR(predicted_frame_ms(m, {true, false}, 44), 44, 1e-9);
  // At 40x the work it pays: T = (1760 + 75/14) / (15/14) = 1648 ms < 1760 ms.
  EXPECT_EQ(choose_participants(m, both, 1760, 0.03), both);
  EXPECT_NEAR(predicted_frame_ms(m, both, 1760), (1760 + 75.0 / 14) / (15.0 / 14), 1e-9);
}

TEST(Participation, OnlyAFixedCostTheFramesShowClearlyCounts) {
  // 75 +- 10 ms is judged as 55 ms (two standard errors below); 232 +- 530 ms (a fit over
  // frames with and without contention) as none.
  const std::vector<bool> both = {true, true};
  EXPECT_NEAR(predicted_frame_ms({model(1, 0), model(1.0 / 14, 75, 10)}, both, 1760),
              (1760 + 55.0 / 14) / (15.0 / 14), 1e-9);
  EXPECT_NEAR(predicted_frame_ms({model(1, 232, 530), model(1, 0)}, both, 100), 50, 1e-9);
}

TEST(Participation, ADeviceMustSaveMoreThanTheMargin) {
  const std::vector<bool> both = {true, true};
  // No fixed cost, 2% of the speed: it would save 2%, not more than 3%.
  EXPECT_EQ(choose_participants({model(1, 0), model(0.02, 0)}, both, 100, 0.03),
            (std::vector<bool>{true, false}));
  EXPECT_EQ(choose_participants({model(1, 0), model(0.02, 0)}, both, 100, 0.01), both);
  EXPECT_EQ(choose_participants({model(1, 0), model(0.5, 2)}, both, 100, 0.03), both);
}

TEST(Participation, UndeterminedAndIneligibleDevices) {
  DeviceCostModel unknown;  // never measured
  unknown.speed = 0.001;
  const std::vector<DeviceCostModel> m = {model(1, 0), unknown, model(1, 500)};
  // The undetermined device takes part; the dropped one (not eligible) does not.
  EXPECT_EQ(choose_participants(m, {true, true, false}, 10, 0.03),
            (std::vector<bool>{true, true, false}));
  // However dear every device is, one takes part: the cheapest.
  EXPECT_EQ(choose_participants({model(1, 900), model(1, 500)}, {true, true}, 10, 0.03),
            (std::vector<bool>{false, true}));
}

TEST(Participation, TheReasonSaysWhy) {
  EXPECT_EQ(left_out_reason(model(1.0 / 14, 75), 44, 0.03),
            "75 ms fixed per frame against a 44 ms frame");
  EXPECT_EQ(left_out_reason(model(0.02, 2), 44, 0.03),
            "it would save less than 3% of a 44 ms frame (2 ms fixed per frame)");
}

// The real pair of issue 50, simulated: a core, and a device 14x slower that renders its
// list in one launch with a fixed cost of 75 ms (as rusticl does).
std::vector<SimDevice> pair_devices() {
  std::vector<SimDevice> d(2);
  d[0].speed = 1;
  d[1].speed = 1.0 / 14;
  d[1].launch_ms = 75;
  return d;
}

const FrameShape kShape{320, 180, 1, {}};

CostFn frame_of(double ms) { return uniform_cost(kShape, ms / double(kShape.pixels())); }

// Plan, simulate, update; the cost of a frame from `ms_at(frame)`.
std::vector<SimFrame> run(Balancer& b, int frames, const std::function<double(int)>& ms_at) {
  std::vector<SimFrame> out;
  for (int f = 0; f < frames; ++f) {
    SimFrame sf = simulate_linked(b.plan(kShape, f), kShape, pair_devices(), frame_of(ms_at(f)),
                                  SimLink{}, f);
    b.update(sf.stats);
    out.push_back(std::move(sf));
  }
  return out;
}

TEST(HybridLeave, ADeviceWhoseFixedCostOutlastsTheFrameCostsNothing) {
  HybridBalancer hybrid(2);
  const auto frames = run(hybrid, 60, [](int) { return 44.0; });
  int rested = 0;
  for (int f = 10; f < 60; ++f) {
    const SimFrame& sf = frames[size_t(f)];
    if (!sf.plan.rests(1)) continue;  // a probe
    ++rested;
    // It gets nothing, is not started and costs nothing: the core alone sets the frame.
    EXPECT_TRUE(sf.plan.assigned[1].empty()) << f;
    EXPECT_EQ(sf.plan.ratios[1], 0.0) << f;
    EXPECT_TRUE(sf.stats.devices[1].rested) << f;
    EXPECT_EQ(sf.stats.devices[1].time_ms, 0.0) << f;
    EXPECT_NEAR(sf.frame_ms, 44.0, 1e-6) << f;
    EXPECT_NE(sf.plan.rest_reason[1].find("ms fixed per frame"), std::string::npos);
    EXPECT_NEAR(sf.plan.models[1].fixed_ms, 75, 5) << f;
  }
  // Probes after 8, 16, 32 frames: at most a handful in 50 frames.
  EXPECT_GE(rested, 45);
  // With the rule off (hybrid before it), every frame waits for the fixed cost.
  HybridBalancer old(2, HybridBalancer::Options{.leave = false});
  const auto before = run(old, 60, [](int) { return 44.0; });
  for (int f = 10; f < 60; ++f) EXPECT_GT(before[size_t(f)].frame_ms, 75.0) << f;
}

TEST(HybridLeave, TheLeftOutDeviceComesBackWhenItPays) {
  // 40x the work from frame 30 on (more samples): the device's 75 ms now buy it a share.
  HybridBalancer hybrid(2);
  const auto frames = run(hybrid, 45, [](int f) { return f < 30 ? 44.0 : 1760.0; });
  ASSERT_TRUE(frames[29].plan.rests(1));
  for (int f = 34; f < 45; ++f) {
    const SimFrame& sf = frames[size_t(f)];
    // Saving ~6%, it is rested for a frame now and then to measure what it saves.
    if (sf.plan.rests(1) && sf.plan.rest_reason[1].rfind("rested for a frame", 0) == 0) continue;
    EXPECT_FALSE(sf.plan.rests(1)) << f;
    EXPECT_GT(sf.plan.ratios[1], 0.01) << f;
    EXPECT_LT(sf.frame_ms, 1760.0 * 0.97) << f;  // faster than the core alone
    // It does not steal: one more launch would outlast the items it took.
    EXPECT_TRUE(sf.plan.no_steal[1]) << f;
    EXPECT_EQ(sf.stats.devices[1].items.size(), sf.plan.assigned[1].size()) << f;
  }
  // Within 0.5% of the best split: T = (1760 + 75/14) / (15/14) = 1647.7 ms.
  EXPECT_NEAR(frames[43].frame_ms, (1760 + 75.0 / 14) / (15.0 / 14), 0.005 * 1648);
}

TEST(Participation, ContentionSlowsTheOthers) {
  // The slow device would save 6% on its own; at work it slows the core by 1.2x.
  DeviceCostModel slow = model(1.0 / 14, 20);
  const std::vector<bool> both = {true, true};
  EXPECT_EQ(choose_participants({model(1, 0), slow}, both, 400, 0.03), both);
  slow.contention = 1 / 1.2;
  EXPECT_EQ(choose_participants({model(1, 0), slow}, both, 400, 0.03),
            (std::vector<bool>{true, false}));
}

// The same device at 400 ms of work, where it would pay alone (6%), on cores it shares
// with the core (each runs 1.2x slower while both work, SimDevice::contention): hybrid
// keeps it at first, rests it for one early frame, measures what it costs the core and
// leaves it out; the frames then take the core's 400 ms.
std::vector<SimFrame> run_contended(HybridBalancer& hybrid, int n, double launch_ms) {
  std::vector<SimFrame> frames;
  for (int f = 0; f < n; ++f) {
    std::vector<SimDevice> d = pair_devices();
    d[1].launch_ms = launch_ms;
    d[0].contention = d[1].contention = 0.2;
    SimFrame sf = simulate_linked(hybrid.plan(kShape, f), kShape, d, frame_of(400), SimLink{}, f);
    hybrid.update(sf.stats);
    frames.push_back(std::move(sf));
  }
  return frames;
}

TEST(HybridLeave, ADeviceThatSlowsTheOthersMoreThanItHelpsIsLeftOut) {
  HybridBalancer hybrid(2);
  const std::vector<SimFrame> frames = run_contended(hybrid, 40, 20);
  EXPECT_FALSE(frames[2].plan.rests(1));  // kept while its contention is unknown
  int rested = 0;
  for (int f = 25; f < 40; ++f) {
    const SimFrame& sf = frames[size_t(f)];
    EXPECT_LT(sf.plan.models[1].contention, 0.9) << f;
    if (!sf.plan.rests(1)) {  // a probe: a small share
      EXPECT_LE(sf.plan.ratios[1], 0.02) << f;
      continue;
    }
    ++rested;
    EXPECT_NEAR(sf.frame_ms, 400, 1e-6) << f;
  }
  EXPECT_GE(rested, 13);
}

// The same without a fixed cost (rusticl at 16 spp: its launch is lost in the slope of its
// fit): nothing in its own times says it does not pay, so it is rested early (two frames
// after its fit is determined) on its small saving alone, and left out from then on.
TEST(HybridLeave, ADeviceWithNoFixedCostThatSlowsTheOthersIsLeftOutEarly) {
  HybridBalancer hybrid(2);
  const std::vector<SimFrame> frames = run_contended(hybrid, 30, 0);
  int first_out = -1;
  for (int f = 0; f < 30 && first_out < 0; ++f)
    if (frames[size_t(f)].plan.rests(1)) first_out = f;
  ASSERT_GE(first_out, 0);
  EXPECT_LE(first_out, 10);
  for (int f = 14; f < 30; ++f) {
    const SimFrame& sf = frames[size_t(f)];
    EXPECT_LT(sf.plan.models[1].contention, 0.9) << f;
    if (sf.plan.rests(1))
      EXPECT_NEAR(sf.frame_ms, 400, 1e-6) << f;
    else
      EXPECT_LE(sf.plan.ratios[1], 0.02) << f;  // a probe
  }
}

}  // namespace participation_test
}  // namespace multiray::balance
