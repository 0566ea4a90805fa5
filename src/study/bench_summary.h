// What `multiray bench` reports per balancer: the summary statistics, the printed table
// and the JSON record. Pure functions of the frame records.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/efficiency.h"
#include "engine/bench_harness.h"
#include "engine/frame_record.h"

namespace multiray::study {

struct RunSummary {
  // Frames >= warm-up; frame time is frame_total_ms().
  double mean_frame_ms = 0, mean_imbalance = 0, mean_deviation = 0;
  // Where the time of the full-quality frames >= warm-up went (balance/efficiency.h): the
  // mean of their breakdowns; invalid when there are none.
  balance::Breakdown breakdown;
  bool stolen_measured = false;  // every device measured its stolen time in those frames
  double wall_ms = 0;            // the engine's mean wall time of those frames
  // breakdown.efficiency(): mean ideal / mean frame time over those frames; 0 when there
  // are none (printed "-", null in JSON).
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

// A value of `frame`, linearly interpolated between the sampled frames (clamped at the
// ends). `sampled` is increasing and non-empty; ms[k] belongs to sampled[k].
double interpolate_ideal(const std::vector<int>& sampled, const std::vector<double>& ms,
                         int frame);

// Each device's alone time at `frame`, interpolated between the timed frames (`ideal` is in
// frame order); empty when no frame was timed.
std::vector<double> alone_at(const std::vector<IdealSample>& ideal, int frame);

// The ideal time of `frame`: 1 / Σ_i 1 / alone_at(i); 0 when no frame was timed.
double ideal_at(const std::vector<IdealSample>& ideal, int frame);

// The mean of ideal_at() over frames [from, to): the ideal frame time that efficiency
// compares against when all those frames are at full quality. 0 if from >= to.
double mean_ideal_ms(const std::vector<IdealSample>& ideal, int from, int to);

// The host's time in a frame around the devices' phase: planning, gathering, the
// balancer's update, an advisor's advice, pre-pass and learning.
double host_ms(const FrameRecord& r);
// A frame's time as the user waits for it: the devices' phase + host_ms().
double frame_total_ms(const FrameRecord& r);

// The frame's time in parts (balance/efficiency.h), with the devices' alone times of
// `ideal` at its frame; invalid when no frame was timed or the devices do not match.
balance::Breakdown frame_breakdown(const FrameRecord& r, const std::vector<IdealSample>& ideal);

// A frame rendered at full quality in one pass: the ideal (timed at full quality) applies.
bool full_quality(const FrameRecord& r);

// The warm-up when --warmup is not given: frames / 4, at most 10 (100 frames: 10; 2 frames:
// none, so a short run needs no option).
int default_warmup(int frames);

// `ideal`: the frames timed alone, in frame order; `perturb_frame` < 0: none.
RunSummary summarize(const std::vector<FrameRecord>& recs, int warmup,
                     const std::vector<IdealSample>& ideal, int perturb_frame);

// Fills in `speedup` from the run whose spec starts with "uniform", if any.
void add_speedups(const std::vector<std::string>& specs, std::vector<RunSummary>& summaries);

// The bit-identity verdict. `mismatched[k]`: the frames in which lane k's images (every
// view) differed from an earlier lane's at the same quality. One entry per such lane,
// "LANE: N frame(s), first F", joined by "; "; empty when every lane agreed.
std::string mismatch_summary(const std::vector<std::string>& lanes,
                             const std::vector<std::vector<int>>& mismatched);

// The comparison table, one line per balancer. Harada's deviation gets a column only where
// it differs from the imbalance (with two devices the two are the same number), recovery
// only when the run was perturbed; a line under the table says which was left out.
void print_table(const std::vector<std::string>& specs, const std::vector<RunSummary>& summaries,
                 bool perturbed);

// Where the time went, one line per balancer (ms per frame), how much of the engine's
// measured wall time the parts account for, and why an efficiency is above 1 if one is.
void print_breakdown(const std::vector<std::string>& specs,
                     const std::vector<RunSummary>& summaries);

nlohmann::json summary_to_json(const RunSummary& s, int warmup, const std::vector<int>& sampled);
nlohmann::json breakdown_to_json(const balance::Breakdown& b, bool stolen_measured,
                                 double wall_ms);

// File-name stems for the lanes' report and trace files: each lane's balancer name, and
// "name-2", "name-3", ... for later lanes of the same name (uniform and
// uniform:layout=strips would otherwise write the same files).
std::vector<std::string> lane_file_stems(const std::vector<std::string>& names);

}  // namespace multiray::study
