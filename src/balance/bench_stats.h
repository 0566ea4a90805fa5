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
  int resamples = 2000;
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

}  // namespace multiray::balance
