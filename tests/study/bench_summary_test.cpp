// The bench command's arithmetic: interpolated ideal, efficiency, recovery, speedup,
// rebalances, the default warm-up and the bit-identity verdict.
#include <gtest/gtest.h>

#include "study/bench_summary.h"

namespace multiray::study {
namespace bench_summary_test {

std::vector<FrameRecord> frames(const std::vector<double>& ms,
                                const std::vector<double>& imbalance) {
  std::vector<FrameRecord> out;
  for (size_t f = 0; f < ms.size(); ++f) {
    FrameRecord r;
    r.frame = int(f);
    r.frame_ms = ms[f];
    r.imbalance = imbalance[f];
    out.push_back(r);
  }
  return out;
}

// One device timed alone on `frames`, taking `ms` there: the ideal is `ms`.
std::vector<IdealSample> timed(const std::vector<int>& frames, const std::vector<double>& ms) {
  std::vector<IdealSample> out;
  for (size_t k = 0; k < frames.size(); ++k) out.push_back(IdealSample{frames[k], {ms[k]}, ms[k]});
  return out;
}

// A rebalance is a frame whose planned shares differ from the previous frame's.
// Two lanes of one balancer (uniform rows and uniform strips) must not write one file.
TEST(BenchSummary, LanesOfOneBalancerGetTheirOwnFiles) {
  EXPECT_EQ(lane_file_stems({"uniform", "dlb", "uniform", "uniform"}),
            (std::vector<std::string>{"uniform", "dlb", "uniform-2", "uniform-3"}));
  EXPECT_TRUE(lane_file_stems({}).empty());
}

TEST(BenchSummary, CountsFramesWhoseSharesChanged) {
  auto recs = frames({1, 1, 1, 1, 1, 1}, {0, 0, 0, 0, 0, 0});
  const double shares[6] = {0.5, 0.5, 0.6, 0.6, 0.6, 0.55};
  for (size_t f = 0; f < recs.size(); ++f) {
    recs[f].devices.resize(2);
    recs[f].devices[0].planned_share = shares[f];
    recs[f].devices[1].planned_share = 1 - shares[f];
  }
  EXPECT_EQ(count_rebalances(recs), 2);  // frames 2 and 5
  EXPECT_EQ(summarize(recs, 0, {}, -1).rebalances, 2);
  recs[3].devices[1].planned_share += 1e-12;  // rounding is not a rebalance
  EXPECT_EQ(count_rebalances(recs), 2);
  EXPECT_EQ(count_rebalances({}), 0);
}

TEST(BenchSummary, InterpolatesIdealBetweenSampledFrames) {
  EXPECT_DOUBLE_EQ(interpolate_ideal({2, 6}, {10, 30}, 4), 20);
  EXPECT_DOUBLE_EQ(interpolate_ideal({2, 6}, {10, 30}, 0), 10);  // clamped
  EXPECT_DOUBLE_EQ(interpolate_ideal({2, 6}, {10, 30}, 9), 30);
  EXPECT_DOUBLE_EQ(interpolate_ideal({2, 6, 8}, {10, 30, 0}, 7), 15);
}

TEST(BenchSummary, PrintedIdealIsTheOneEfficiencyUses) {
  // Timed on frames 2 and 3 (10 and 40 ms); frames 4-5 are clamped to 40 ms. The plain
  // mean of the timed frames (25 ms) is not what efficiency compares against: 32.5 ms is.
  const std::vector<int> sampled{2, 3};
  const std::vector<double> ideal{10, 40};
  EXPECT_DOUBLE_EQ(mean_ideal_ms(timed(sampled, ideal), 2, 6), 32.5);
  EXPECT_DOUBLE_EQ(mean_ideal_ms(timed(sampled, ideal), 2, 2), 0);  // no frames
  const auto recs = frames({100, 100, 65, 65, 65, 65}, {0, 0, 0, 0, 0, 0});
  const RunSummary s = summarize(recs, 2, timed(sampled, ideal), -1);
  EXPECT_DOUBLE_EQ(s.ideal_ms, 32.5);
  EXPECT_DOUBLE_EQ(s.efficiency, 0.5);
  EXPECT_DOUBLE_EQ(s.efficiency, s.ideal_ms / s.mean_frame_ms);
  EXPECT_DOUBLE_EQ(summary_to_json(s, 2, sampled)["ideal_ms"].get<double>(), 32.5);
}

TEST(BenchSummary, DefaultWarmupLeavesShortRunsAFrameToSummarise) {
  EXPECT_EQ(default_warmup(100), 10);
  EXPECT_EQ(default_warmup(1000), 10);
  EXPECT_EQ(default_warmup(20), 5);
  EXPECT_EQ(default_warmup(2), 0);
  EXPECT_EQ(default_warmup(1), 0);
}

TEST(BenchSummary, MismatchNamesEachLaneWhoseImagesDiffered) {
  EXPECT_EQ(mismatch_summary({"uniform", "hybrid"}, {{}, {}}), "");
  EXPECT_EQ(mismatch_summary({"uniform", "hybrid", "queue"}, {{}, {3, 7}, {1}}),
            "hybrid: 2 frame(s), first 3; queue: 1 frame(s), first 1");
}

TEST(BenchSummary, EfficiencyRecoveryAndSpeedup) {
  // Frames 0-1 are warm-up; the ideal is 10 ms everywhere; actual 20 ms then 10 ms.
  const auto recs = frames({100, 100, 20, 20, 10, 10}, {0.5, 0.5, 0.2, 0.1, 0.04, 0.0});
  const RunSummary s = summarize(recs, 2, timed({2, 5}, {10, 10}), 3);
  EXPECT_DOUBLE_EQ(s.mean_frame_ms, 15);
  EXPECT_DOUBLE_EQ(s.efficiency, 40.0 / 60.0);
  EXPECT_EQ(s.recovery_frames, 1);  // frame 4 is the first under 5% after frame 3
  std::vector<RunSummary> all{s, s};
  all[0].mean_frame_ms = 30;
  add_speedups({"uniform:layout=rows", "hybrid"}, all);
  EXPECT_DOUBLE_EQ(all[1].speedup, 2.0);
  EXPECT_DOUBLE_EQ(all[0].speedup, 1.0);
}

TEST(BenchSummary, RecoveryIsWhereImbalanceStaysUnder5PercentToTheEnd) {
  // Perturbation at frame 1: frame 2 dips under 5% but frame 3 is back above it, so the
  // run recovers at frame 4 (3 frames), not at the first frame under 5%.
  const auto recs = frames({10, 10, 10, 10, 10, 10}, {0.01, 0.3, 0.03, 0.2, 0.04, 0.01});
  EXPECT_EQ(summarize(recs, 0, timed({0}, {10}), 1).recovery_frames, 3);
  // Over 5% in the last frame: not recovered, whatever came before.
  const auto late = frames({10, 10, 10, 10}, {0.01, 0.3, 0.01, 0.06});
  EXPECT_EQ(summarize(late, 0, timed({0}, {10}), 1).recovery_frames, -1);
  EXPECT_EQ(summarize(late, 0, timed({0}, {10}), -1).recovery_frames, -1);  // no perturbation
}

TEST(BenchSummary, EfficiencyLeavesOutFramesBelowFullQuality) {
  // The ideal is timed at full quality: a frame rendered coarser (frame-time targeting)
  // or in two passes would make the efficiency look better than 1.
  auto recs = frames({20, 20, 5, 5}, {0, 0, 0, 0});
  recs[2].quality.step_scale = 4;
  recs[3].first_pass_ms = 1;
  EXPECT_DOUBLE_EQ(summarize(recs, 0, timed({0, 3}, {10, 10}), -1).efficiency, 0.5);
  recs[0].quality.image_scale = recs[1].quality.image_scale = 0.5;
  EXPECT_EQ(summarize(recs, 0, timed({0, 3}, {10, 10}), -1).efficiency,
            0);  // none at full quality
}

}  // namespace bench_summary_test
}  // namespace multiray::study
