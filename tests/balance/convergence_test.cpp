// Every adaptive balancer on synthetic devices: converges to ratios proportional to
// speed, does not oscillate under ±5% noise, handles uneven pixel cost, and recovers after
// a speed change within a stated number of frames.
#include <gtest/gtest.h>

#include <cmath>

#include "balance/balancer.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace convergence_test {

using namespace testing;

struct Case {
  friend void PrintTo(const Case& c, std::ostream* os) { *os << c.spec; }
  std::string spec;
  int warmup;        // frames before the ratios are expected to have converged
  double ratio_tol;  // relative error allowed on each planned ratio
  double imbalance;  // mean imbalance allowed after warmup, flat cost
  double uneven;     // the same with uneven pixel cost
  int recovery;      // frames after a speed change until imbalance stays < 5%
};

// recovery: semi-static is a blend (α = 0.4: the error shrinks 0.6× a frame); dlb waits
// for its check every 5 frames and may need two; hybrid steals within the frame of the
// change (which stays under 10%, see below) and plans with the new speed from the next.
//
// The peers' balancers (peers_*.h), with what their designs allow: cycles stops inside
// its 2% dead band (a pair may stay up to 4% apart, a share ~4.5% off) and moves each
// device only 1/N of the way per rebalance (20 frames for 5 devices); its own 1 s
// interval is ~17 frames here, longer than the 20 frames after the change this test
// watches, so the case runs at 250 ms (peers_test.cpp tests the interval itself).
// equalizer damps every level of its tree by 0.5 (8 devices settle in ~35 frames) and
// gives each device one rectangle, so the 49-pixel-wide column of the 0.5-speed device
// is 2% off by rounding alone. ospray-dynamic is a queue (tile 16 here, as queue's 32).
// Like uniform and static, ospray-static never adapts and is not listed.
const std::vector<Case> kCases = {
    {"semi-static", 15, 0.02, 0.01, 0.01, 6},
    {"dlb", 5, 0.02, 0.02, 0.02, 10},
    {"hybrid", 1, 0.02, 0.01, 0.01, 1},
    {"hybrid:steal=0", 4, 0.02, 0.01, 0.01, 3},
    {"queue:tile=32", 1, 0.05, 0.03, 0.05, 0},
    {"cycles:interval_ms=250", 20, 0.05, 0.035, 0.04, 10},
    {"equalizer", 35, 0.03, 0.02, 0.01, 3},
    {"ospray-dynamic:tile=16", 1, 0.05, 0.03, 0.05, 0},
};

class Convergence : public ::testing::TestWithParam<Case> {};

const FrameShape kShape{640, 360, 1, {}};

TEST_P(Convergence, RatiosFollowSpeeds) {
  const Case& c = GetParam();
  for (const std::vector<double>& speeds :
       {std::vector<double>{3, 1}, {4, 1, 2, 0.5, 3}, {1, 1, 1, 1, 1, 1, 1, 8}}) {
    const auto b = make_balancer(c.spec, int(speeds.size()));
    const auto run = simulate_run(*b, kShape, constant(speeds), flat_cost(kShape), c.warmup + 10);
    for (int f = c.warmup; f < int(run.size()); ++f) {
      // Over the devices taking part: hybrid rests a device that saves under 10% for one
      // early frame, to measure what it saves (participation.h); that device plans 0.
      const Plan& plan = run[size_t(f)].plan;
      double total = 0;
      for (size_t i = 0; i < speeds.size(); ++i) total += plan.rests(int(i)) ? 0 : speeds[i];
      for (size_t i = 0; i < speeds.size(); ++i) {
        const double want = plan.rests(int(i)) ? 0 : speeds[i] / total;
        EXPECT_NEAR(planned(run[size_t(f)], int(i)), want, c.ratio_tol * speeds[i] / total)
            << c.spec << " frame " << f << " device " << i << " of " << speeds.size();
      }
    }
    EXPECT_LE(mean_imbalance(run, c.warmup, int(run.size())), c.imbalance) << c.spec;
  }
}

TEST_P(Convergence, BalancesUnevenPixelCost) {
  const Case& c = GetParam();
  const auto b = make_balancer(c.spec, 2);
  const auto run = simulate_run(*b, kShape, constant({3, 1}), uneven_cost(kShape), 40);
  EXPECT_LE(mean_imbalance(run, 20, 40), c.uneven) << c.spec;
}

// Not a limit cycle: the planned share does not flip direction more often than noise makes
// it. With noise alone, the most a balancer that does not over-correct can do is follow
// each frame's measurement (queue: its ratios are last frame's shares). Its share is then
// an i.i.d. sequence, and n i.i.d. values have 2(n − 2)/3 direction flips (turning points)
// on average, variance (16n − 29)/90, whatever their distribution. The bound is that mean
// + 3 sd: over frames 20–319 (n = 300), 198.7 + 3 · 7.3 = 220.5 of 298 chances (0.74).
//
// Correcting by a gain g of the measured error flips with probability ≈ 1/2 + asin(g/2)/π:
// smoothing flips less (semi-static's blend, g = α = 0.4: 0.56), dead bands hold the share
// (dlb, cycles: none); over-correction flips more (g = 1.5: 0.77, 229 flips), and a share
// pushed up and down on alternate frames flips every frame. Measured with seed 5: queue
// 0.62, ospray-dynamic 0.59, hybrid 0.58, semi-static 0.56, equalizer 0.43 of the chances.
//
// The run is this long to tell them apart: over frames 20–79 noise alone gives 38.7 ± 3.2
// flips and g = 1.5 only 44.7, so any bound there fails a noise follower now and then or
// lets a mild limit cycle pass. Checked by hand: semi-static and hybrid:steal=0 with ±0.3%
// added to the share on alternate frames (a fifth of the ±1.5% the noise moves it) pass
// the deviation and imbalance checks below but make 226 and 252 flips; over frames 20–79
// semi-static made 42, under the bound of 45 this test had before.
constexpr int kNoiseFrames = 320;

double most_flips_of_noise(int n) {
  return 2.0 * (n - 2) / 3 + 3 * std::sqrt((16.0 * n - 29) / 90);
}

TEST_P(Convergence, DoesNotOscillateUnderNoise) {
  const Case& c = GetParam();
  const auto b = make_balancer(c.spec, 2);
  const auto run =
      simulate_run(*b, kShape, constant({3, 1}, 0.05), flat_cost(kShape), kNoiseFrames, 5);
  // ±5% on each device's speed moves the ideal share of device 0 by about ±1.5%.
  EXPECT_LE(stddev_of_share(run, 0, 20, kNoiseFrames), 0.01) << c.spec;
  EXPECT_LE(mean_imbalance(run, 20, kNoiseFrames), 0.04) << c.spec;
  EXPECT_LE(direction_flips(run, 0, 20, kNoiseFrames), most_flips_of_noise(kNoiseFrames - 20))
      << c.spec;
}

TEST_P(Convergence, RecoversAfterSpeedChange) {
  const Case& c = GetParam();
  const int at = 30;
  const auto b = make_balancer(c.spec, 2);
  // Device 0 drops from 3 to 1.5 at frame 30 (the perturbation benchmark).
  const auto run = simulate_run(*b, kShape, speed_step({3, 1}, {1.5, 1}, at, 0.02),
                                flat_cost(kShape), at + 20, 9);
  const int settled = settles_at(run, at, 0.05);
  ASSERT_GE(settled, 0) << c.spec << " never settles";
  EXPECT_LE(settled - at, c.recovery) << c.spec;
  EXPECT_NEAR(planned(run.back(), 0), 0.6, 0.02) << c.spec;
  if (c.spec == "hybrid") {
    EXPECT_LT(imbalance(run[at].stats), 0.1);
  }
}

INSTANTIATE_TEST_SUITE_P(Adaptive, Convergence, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           std::string n;
                           for (char ch : p.param.spec) n += std::isalnum(ch) ? ch : '_';
                           return n;
                         });

TEST(Recovery, FirstFrameFromWhichImbalanceStaysUnderTheLimit) {
  const std::vector<double> lambda{0.5, 0.04, 0.2, 0.01, 0.049, 0.0};
  EXPECT_EQ(recovered_from(lambda, 0), 3);  // frame 1 dips under 5%, frame 2 is back over
  EXPECT_EQ(recovered_from(lambda, 4), 4);  // counted from `from` on
  EXPECT_EQ(recovered_from(lambda, 3, 0.01), 5);
  EXPECT_EQ(recovered_from({0.01, 0.06}, 0), -1);  // over the limit at the end
  EXPECT_EQ(recovered_from(lambda, 6), -1);        // `from` past the end
}

TEST(Static, GivenRatiosAreKeptForEver) {
  const auto b = make_balancer("static:ratios=3/0/1", 3);
  const auto run = simulate_run(*b, kShape, constant({1, 1, 1}), flat_cost(kShape), 5);
  for (const SimFrame& f : run) {
    EXPECT_DOUBLE_EQ(planned(f, 0), 0.75);
    EXPECT_DOUBLE_EQ(planned(f, 1), 0.0);
    EXPECT_TRUE(f.plan.assigned[1].empty());
  }
}

TEST(Static, CalibratesOnceFromTheFirstFrame) {
  const auto b = make_balancer("static", 2);
  // The speed change at frame 3 is not followed: that is what `static` means.
  const auto run = simulate_run(*b, kShape, speed_step({3, 1}, {1, 1}, 3), flat_cost(kShape), 6);
  EXPECT_DOUBLE_EQ(planned(run[0], 0), 0.5);
  for (int f = 1; f < 6; ++f) EXPECT_NEAR(planned(run[size_t(f)], 0), 0.75, 1e-3);
  EXPECT_LT(imbalance(run[2].stats), 0.01);
  EXPECT_GT(imbalance(run[4].stats), 0.3);
}

TEST(Static, CalibrationWaitsForUsableTimings) {
  const auto b = make_balancer("static", 2);
  FrameStats bad =
      simulate(b->plan(kShape, 0), kShape, devices_with_speeds({3, 1}), flat_cost(kShape));
  bad.devices[1].time_ms = std::numeric_limits<double>::quiet_NaN();
  b->update(bad);
  EXPECT_DOUBLE_EQ(b->plan(kShape, 1).ratios[0], 0.5);  // still uncalibrated
  b->update(simulate(b->plan(kShape, 1), kShape, devices_with_speeds({3, 1}), flat_cost(kShape)));
  EXPECT_NEAR(b->plan(kShape, 2).ratios[0], 0.75, 1e-3);
}

TEST(Uniform, EvenSharesInEveryLayout) {
  for (const std::string spec : {"uniform", "uniform:layout=columns", "uniform:layout=strips"}) {
    const auto b = make_balancer(spec, 4);
    const auto run = simulate_run(*b, kShape, constant({4, 3, 2, 1}), flat_cost(kShape), 3);
    for (const SimFrame& f : run)
      for (int i = 0; i < 4; ++i) {
        EXPECT_DOUBLE_EQ(planned(f, i), 0.25) << spec;
        // Bands are whole rows; strips are 56 or 57 px (2^12 of them): a pixel per strip.
        const double slack = spec == "uniform:layout=strips" ? 4096 / 4.0 : 640.0;
        EXPECT_NEAR(f.stats.devices[size_t(i)].pixels, 640 * 360 / 4.0, slack) << spec;
      }
  }
}

TEST(Queue, EverythingIsSharedInTilesAndBatches) {
  const auto b = make_balancer("queue:tile=100:batch=3", 2);
  const Plan p = b->plan(FrameShape{250, 120, 2, {}}, 0);
  EXPECT_TRUE(p.assigned[0].empty() && p.assigned[1].empty());
  EXPECT_EQ(p.batch, 3);
  EXPECT_FALSE(p.steal);
  ASSERT_EQ(p.shared.size(), 12u);  // 3×2 tiles per view
  EXPECT_EQ(p.shared[2].rect, (Rect{200, 0, 250, 100}));
  EXPECT_EQ(p.shared[6].view, 1);
}

}  // namespace convergence_test
}  // namespace multiray::balance
