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

namespace multiray::app {

struct RepeatLane {
  std::string label;
  balance::Blocks frame_ms;    // per block, per frame >= warm-up
  balance::Blocks efficiency;  // per block, per frame: the frame's ideal / its time
};

struct RepeatSummary {
  int blocks = 0;
  std::vector<std::string> labels;
  std::vector<balance::Interval> efficiency;  // per lane
  balance::Verdict time;                      // frame time: medians, ratios, winner or ties
};

// Appends one block's figures of every lane of `r` (frames [warmup, end)); `lanes` is
// sized from `labels` on the first call.
void add_block(std::vector<RepeatLane>& lanes, const std::vector<std::string>& labels,
               const BenchResult& r, int warmup);

RepeatSummary summarize_repeats(const std::vector<RepeatLane>& lanes);

// The table (median [95% interval] of frame time, efficiency and the ratio to the best)
// and the verdict line.
void print_repeats(const RepeatSummary& s);

nlohmann::json repeats_to_json(const RepeatSummary& s);

}  // namespace multiray::app
