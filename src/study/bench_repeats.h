// `multiray bench --repeats K`: the run is repeated in K blocks (each a fresh session of
// every balancer over the same frames, interleaved frame by frame), and every lane's
// per-frame figures are summarised as medians with 95% intervals (balance/bench_stats.h).
// The verdict names a winner only where the intervals of the per-frame ratios separate.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/bench_stats.h"
#include "engine/bench_harness.h"
#include "study/bench_summary.h"
#include "study/report_plots.h"

namespace multiray::study {

struct RepeatLane {
  std::string label;
  balance::Blocks frame_ms;              // per block, per frame >= warm-up: frame_total_ms()
  balance::Blocks efficiency;            // per block, per full-quality frame: its ideal / its time
  balance::Blocks imbalance, deviation;  // per block, per frame >= warm-up
  balance::Blocks recovery;              // per block, one value: frames (none: never)
};

struct RepeatSummary {
  int blocks = 0;
  std::vector<std::string> labels;
  // Per lane; recovery only when perturbed (invalid otherwise, or when no block recovered).
  std::vector<balance::Interval> efficiency, imbalance, deviation, recovery;
  bool perturbed = false;  // recovery is shown ("never" where no block recovered)
  std::vector<std::vector<double>> block_medians;  // per lane, per block: frame time
  // Per lane, the blocks that recovered (the recovery interval is over those only).
  std::vector<int> recovered_blocks;
  balance::Verdict time;  // frame time: medians, ratios, winner or ties
};

// Appends one block's figures of every lane of `r` (frames [warmup, end)); `lanes` is
// sized from `labels` on the first call. `perturb_frame` < 0: none.
void add_block(std::vector<RepeatLane>& lanes, const std::vector<std::string>& labels,
               const BenchResult& r, int warmup, int perturb_frame);

RepeatSummary summarize_repeats(const std::vector<RepeatLane>& lanes, bool perturbed);

// The table (median [95% interval] of frame time, efficiency, imbalance, recovery when
// perturbed, and the ratio to the best) and the verdict line.
void print_repeats(const RepeatSummary& s);

nlohmann::json repeats_to_json(const RepeatSummary& s);

// bench --regret (regret_lanes): the `auto` lane's frame time over the fastest `subset`
// lane's, median [95% interval] of the per-frame ratios of those two lanes, and a line
// ("regret: auto 36.4 ms, best subset subset:devices=0 33.7 ms: 1.08x [1.05, 1.10]").
// {"ratio": {median, lo, hi}, "best_subset", "text"}; text only when nothing is known.
nlohmann::json regret_of(const std::vector<RepeatLane>& lanes, const RepeatSummary& s);

// The bars of comparison.svg: with several blocks the repeat medians and intervals, with
// one the block's means (no intervals).
std::vector<ComparisonBar> comparison_bars(const RepeatSummary& repeats,
                                           const std::vector<RunSummary>& block0);

// The noise gate over the run (balance::noise_gate): one line on stdout when the machine
// was quiet enough, one warning line on stderr when it was not.
balance::NoiseVerdict judge_noise(balance::NoiseReadings& readings,
                                  const std::vector<RepeatLane>& lanes);
void print_noise(const balance::NoiseReadings& readings, const balance::NoiseVerdict& verdict);
nlohmann::json noise_to_json(const balance::NoiseReadings& readings,
                             const balance::NoiseVerdict& verdict);

}  // namespace multiray::study
