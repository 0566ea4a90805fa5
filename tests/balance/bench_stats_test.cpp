// The bench's statistics where the truth is known: simulated devices with injected noise,
// whose population median frame time is measured on a long run; the 95% intervals of many
// short benches must cover it about 95% of the time (at least 90 of 100), and the verdict
// must name a winner only where the intervals separate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "balance/bench_stats.h"
#include "balance/simulate.h"

namespace multiray::balance {
namespace bench_stats_test {

// Frame times (ms) of `frames` frames of `spec` on two noisy devices (3:1, each frame's
// speed off by up to 30%, each item's cost by up to 20%), from `seed`.
std::vector<double> frame_times(const std::string& spec, int frames, uint64_t seed) {
  const FrameShape shape{64, 36, 1, {}, {}};
  auto balancer = make_balancer(spec, 2);
  auto devices = [](int) {
    std::vector<SimDevice> d(2);
    d[0].speed = 1.0, d[1].speed = 1.0 / 3.0;
    for (SimDevice& x : d) x.frame_noise = 0.3, x.item_noise = 0.2;
    return d;
  };
  const auto run =
      simulate_run(*balancer, shape, devices, uniform_cost(shape, 1e-3), frames, seed);
  std::vector<double> t;
  for (const SimFrame& f : run) t.push_back(f.frame_ms);
  return t;
}

double population_median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Three blocks of 20 frames after 5 warm-up frames, each block its own run (seed).
Blocks bench_blocks(const std::string& spec, uint64_t seed) {
  Blocks b;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> t = frame_times(spec, 25, seed * 7919 + uint64_t(k));
    b.emplace_back(t.begin() + 5, t.end());
  }
  return b;
}

TEST(BenchStats, IntervalsCoverTheTrueMedianOfSimulatedNoise) {
  std::vector<double> long_run = frame_times("queue", 20000, 123456);
  long_run.erase(long_run.begin(), long_run.begin() + 5);
  const double truth = population_median(long_run);
  int covered = 0;
  for (uint64_t bench = 1; bench <= 100; ++bench) {
    const Interval i = bootstrap_median(bench_blocks("queue", bench), {.resamples = 1000});
    ASSERT_TRUE(i.valid);
    EXPECT_LE(i.lo, i.median);
    EXPECT_GE(i.hi, i.median);
    covered += i.lo <= truth && truth <= i.hi;
  }
  std::printf("true median %.4f ms: covered by %d of 100 intervals\n", truth, covered);
  EXPECT_GE(covered, 90);
  EXPECT_LE(covered, 100);
}

TEST(BenchStats, PairedRatiosAndVerdictNameAWinnerOnlyWhenSeparated) {
  // Lane a is 10% slower than b on every frame, with frame noise shared by both (paired).
  Blocks a, b, c;
  for (int k = 0; k < 3; ++k) {
    a.emplace_back(), b.emplace_back(), c.emplace_back();
    for (int f = 0; f < 30; ++f) {
      const double noise = 1.0 + 0.3 * std::sin(1.7 * f + k);
      b.back().push_back(10 * noise);
      a.back().push_back(11 * noise * (1.0 + 0.01 * std::cos(3.1 * f)));
      c.back().push_back(10 * noise * (1.0 + 0.02 * std::sin(2.3 * f + k)));  // b's equal
    }
  }
  // Unpaired, the 10% difference drowns in the shared 30% noise.
  EXPECT_FALSE(separated(bootstrap_median(a), bootstrap_median(b)));
  // Paired per frame, it stands out; b and c are tied whichever has the lower median.
  const Verdict v = verdict({"a", "b", "c"}, {a, b, c});
  ASSERT_TRUE(v.best == 1 || v.best == 2) << v.text;
  EXPECT_EQ(v.tied, std::vector<int>{v.best == 1 ? 2 : 1}) << v.text;
  EXPECT_GT(v.ratios[0].lo, 1.05);
  EXPECT_LT(v.ratios[0].hi, 1.15);
  EXPECT_FALSE(v.ratios[size_t(v.best)].valid);
  EXPECT_NE(v.text.find("tied"), std::string::npos) << v.text;
  EXPECT_NE(v.text.find("slower: a 1.1"), std::string::npos) << v.text;
  // Without c, b is named fastest.
  const Verdict two = verdict({"a", "b"}, {a, b});
  EXPECT_EQ(two.best, 1);
  EXPECT_TRUE(two.tied.empty());
  EXPECT_EQ(two.text.rfind("b is fastest", 0), 0u) << two.text;
}

TEST(BenchStats, EmptyAndNonFiniteValuesAreIgnored) {
  EXPECT_FALSE(bootstrap_median({}).valid);
  EXPECT_FALSE(bootstrap_median({{}, {NAN}}).valid);
  const Interval i = bootstrap_median({{1, 2, NAN, 3}, {}, {INFINITY}});
  EXPECT_TRUE(i.valid);
  EXPECT_DOUBLE_EQ(i.median, 2.0);
  EXPECT_TRUE(paired_ratios({{1, 2}}, {{0, 4}})[0] == std::vector<double>{0.5});
}

// The noise gate: a quiet run passes; a low probe, steal or a spread between blocks each
// fail it with their number in the one-line reason; an unmeasured probe (NaN) is skipped.
TEST(BenchStats, NoiseGateNamesEveryLimitExceeded) {
  NoiseReadings quiet;
  quiet.probe_before = 0.98, quiet.probe_after = 0.97;
  quiet.lane_frame_ms = {Blocks{{10, 10.2, 9.9}, {10.1, 10.3}, {9.8, 10}}};
  const NoiseVerdict ok = noise_gate(quiet);
  EXPECT_TRUE(ok.trustworthy);
  EXPECT_EQ(ok.reason, "");
  EXPECT_NEAR(ok.spread, (10.2 - 9.9) / 10.0, 1e-12);  // block medians 10, 10.2, 9.9

  NoiseReadings busy = quiet;
  busy.probe_after = 0.61;
  NoiseVerdict v = noise_gate(busy);
  EXPECT_FALSE(v.trustworthy);
  EXPECT_NE(v.reason.find("0.61 after"), std::string::npos) << v.reason;

  busy = quiet;
  busy.probe_before = 1.55;  // the solo loop slowed: as unsteady as a slow pair
  v = noise_gate(busy);
  EXPECT_FALSE(v.trustworthy);
  EXPECT_NE(v.reason.find("1.55 before"), std::string::npos) << v.reason;

  busy = quiet;
  busy.steal = 0.05;
  v = noise_gate(busy);
  EXPECT_FALSE(v.trustworthy);
  EXPECT_NE(v.reason.find("stole 5.0%"), std::string::npos) << v.reason;

  busy = quiet;
  busy.lane_frame_ms.push_back(Blocks{{20, 20}, {26, 26}});
  busy.lane_names = {"queue", "hybrid"};
  v = noise_gate(busy);
  EXPECT_EQ(v.spread_lane, 1);
  EXPECT_NE(v.reason.find("hybrid's frame time differs by 26%"), std::string::npos) << v.reason;
  EXPECT_FALSE(v.trustworthy);
  EXPECT_NEAR(v.spread, 6.0 / 23.0, 1e-12);
  EXPECT_NE(v.reason.find("26%"), std::string::npos) << v.reason;
  EXPECT_EQ(v.reason.find(';'), std::string::npos) << v.reason;  // one cause, one clause

  NoiseReadings unprobed = quiet;
  unprobed.probe_before = unprobed.probe_after = std::nan("");
  EXPECT_TRUE(noise_gate(unprobed).trustworthy);
  unprobed.lane_frame_ms = {Blocks{{10, 10}}};  // one block: no spread
  EXPECT_EQ(noise_gate(unprobed).spread, 0);
}

}  // namespace bench_stats_test
}  // namespace multiray::balance
