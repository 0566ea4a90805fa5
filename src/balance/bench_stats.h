// Statistics for comparing balancers on repeated runs (`multiray bench --repeats K`).
// A figure is per frame, grouped by repeat block (a block runs every balancer over the same
// frames, interleaved). Its summary is the median with a 95% interval from a two-level
// bootstrap: resample the blocks with replacement, then the frames within each resampled
// block, and take the median of what was drawn. Resampling blocks carries what changes
// between repeats (the machine's load, a device's clock) into the interval; resampling
// frames carries the frame-to-frame noise. Pure functions over plain vectors; a fixed
// seed makes every interval reproducible.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace multiray::balance {

// A median with the bounds of its interval (lo <= median <= hi up to resampling).
struct Interval {
  double median = 0, lo = 0, hi = 0;
  bool valid = false;  // false: no values
};

// Per block, per frame values of one figure (blocks may differ in length; non-finite
// values are ignored).
using Blocks = std::vector<std::vector<double>>;

struct BootstrapOptions {
  int resamples = 2000;  // 0: the median alone (lo = hi = median)
  double confidence = 0.95;
  uint64_t seed = 0x6d756c7469726179ull;  // "multiray"
};

// The median of every value and its two-level bootstrap interval.
Interval bootstrap_median(const Blocks& values, const BootstrapOptions& o = {});

// Per frame ratios a / b of two lanes measured on the same frames (same shape); frames
// where b is not > 0 are left out.
Blocks paired_ratios(const Blocks& a, const Blocks& b);

// True when the intervals do not overlap: only then is a difference called.
bool separated(const Interval& a, const Interval& b);

// The verdict over lanes of a "lower is better" figure (frame time) measured on the same
// frames: the lane with the lowest median is the best; every other lane's per-frame ratio
// to it gets an interval, and a lane whose interval includes 1 is tied with the best.
struct Verdict {
  std::vector<Interval> medians;  // per lane
  std::vector<Interval> ratios;   // per lane, to the best (the best's own: invalid)
  int best = -1;
  std::vector<int> tied;  // lanes tied with the best
  std::string text;       // "hybrid is fastest; slower: queue 1.07x [1.03, 1.12]", or
                          // "hybrid, queue are tied (...); slower: static 1.31x [...]"
};
Verdict verdict(const std::vector<std::string>& names, const std::vector<Blocks>& lanes,
                const BootstrapOptions& o = {});

// Whether the machine was quiet enough for a bench's figures to be trusted: what was
// measured around the run, and the limits it is held to.
struct NoiseReadings {
  // contention_probe() before and after the run: 1 when nothing else ran; NaN: not measured.
  double probe_before = 1, probe_after = 1;
  double steal = 0;                     // the hypervisor's share of all CPU time during the run
  std::vector<Blocks> lane_frame_ms;    // per lane, per block, per frame: for the spread
  std::vector<std::string> lane_names;  // for the reason (may be empty)
};
struct NoiseLimits {
  double min_probe = 0.85;   // below: other programs took a core's time
  double max_probe = 1.18;   // above: the solo loop was the one slowed (the machine is unsteady)
  double max_steal = 0.02;   // above: the hypervisor took more than 2%
  double max_spread = 0.10;  // above: a lane's block medians differ by more than 10%
};
struct NoiseVerdict {
  // The largest over lanes of (max - min) / median of the lane's block medians of frame
  // time; 0 with one block.
  double spread = 0;
  int spread_lane = -1;  // the lane with that spread (-1: none)
  bool trustworthy = true;
  std::string reason;  // "" when trustworthy; otherwise every limit exceeded, in one line
};
NoiseVerdict noise_gate(const NoiseReadings& r, const NoiseLimits& limits = {});

}  // namespace multiray::balance
