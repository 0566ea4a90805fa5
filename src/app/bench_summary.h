// What `multiray bench` reports per balancer: the summary statistics, the printed table
// and the JSON record. Pure functions of the frame records.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/frame_record.h"

namespace multiray::app {

struct RunSummary {
  double mean_frame_ms = 0, mean_imbalance = 0, mean_deviation = 0;  // frames >= warm-up
  // Sum of ideal / sum of actual frame times over full-quality frames >= warm-up; 0 when
  // there are none (printed "-", null in JSON).
  double efficiency = 0;
  // The mean over those same frames of the ideal efficiency compares against (interpolated
  // per frame, interpolate_ideal); 0 when there are none. When every frame >= warm-up is at
  // full quality, efficiency = ideal_ms / mean_frame_ms.
  double ideal_ms = 0;
  double speedup = 0;  // uniform's mean frame time / this one's (0: no uniform run)
  // Frames from the perturbation to the first frame from which imbalance stays < 5% to the
  // end of the run (balance::recovered_from); -1: none, or imbalance >= 5% at the end.
  int recovery_frames = -1;
  // Frames of the whole run whose planned shares differ from the previous frame's (by
  // more than 1e-9 for some device): dlb's ratio recomputations (Leria et al.: a
  // homogeneous pair must never rebalance), semi-static's updates, and so on.
  int rebalances = 0;
};

// rebalances of RunSummary over `recs`.
int count_rebalances(const std::vector<FrameRecord>& recs);

// The ideal time of `frame`, linearly interpolated between the sampled frames (clamped at
// the ends). `sampled` is increasing and non-empty; ideal_ms[k] belongs to sampled[k].
double interpolate_ideal(const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                         int frame);

// The mean of interpolate_ideal() over frames [from, to): the ideal frame time that
// efficiency compares against when all those frames are at full quality. 0 if from >= to.
double mean_ideal_ms(const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                     int from, int to);

// The warm-up when --warmup is not given: frames / 4, at most 10 (100 frames: 10; 2 frames:
// none, so a short run needs no option).
int default_warmup(int frames);

// `ideal_ms[k]` is the ideal time of frame `sampled[k]`; `perturb_frame` < 0: none.
RunSummary summarize(const std::vector<FrameRecord>& recs, int warmup,
                     const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                     int perturb_frame);

// Fills in `speedup` from the run whose spec starts with "uniform", if any.
void add_speedups(const std::vector<std::string>& specs, std::vector<RunSummary>& summaries);

// The bit-identity verdict. `mismatched[k]`: the frames in which lane k's images (every
// view) differed from an earlier lane's at the same quality. One entry per such lane,
// "LANE: N frame(s), first F", joined by "; "; empty when every lane agreed.
std::string mismatch_summary(const std::vector<std::string>& lanes,
                             const std::vector<std::vector<int>>& mismatched);

// The comparison table, one line per balancer.
void print_table(const std::vector<std::string>& specs, const std::vector<RunSummary>& summaries);

nlohmann::json summary_to_json(const RunSummary& s, int warmup, const std::vector<int>& sampled);

}  // namespace multiray::app
