// Pictures for people: per-balancer timing plots (SVG) and partition images (PNG).
#pragma once

#include <string>
#include <vector>

#include "balance/bench_stats.h"
#include "balance/plan.h"
#include "engine/bench_harness.h"
#include "engine/frame_record.h"

namespace multiray::study {

// What a run's timelines share: the time axis of every balancer of the run reaches at
// least `time_max_ms` (so they compare at a glance), the warm-up frames are shaded, and
// `ideal_share[frame][device]` (each device's speed alone over their sum; empty: none) is
// drawn over the stacked shares.
struct TimelineScale {
  double time_max_ms = 0;
  int warmup = 0;
  std::vector<std::vector<double>> ideal_share;
};

// The scale of every timeline of a bench run: the longest device time of any lane after
// the warm-up, the warm-up, and per frame the ideal shares from the devices timed alone
// (interpolated linearly in speed between the timed frames, clamped at the ends).
TimelineScale timeline_scale(const BenchResult& result, int warmup, size_t frames);

// Per-device time per frame (lines, top) and work shares stacked beneath (bottom), on the
// frame axis with numbered ticks. `labels` name the devices (emulated ones should say so).
void write_timeline_svg(const std::string& path, const std::string& title,
                        const std::vector<FrameRecord>& frames,
                        const std::vector<std::string>& labels, const TimelineScale& scale = {});

// One bar per balancer of a run, in three groups with their values printed: efficiency,
// imbalance (as a fraction) and frame time, each with its 95% interval as whiskers.
struct ComparisonBar {
  std::string name;
  // Each a value (median) with its 95% interval; an interval with lo == hi (one block) is
  // drawn without whiskers, an invalid one as "-".
  balance::Interval efficiency, imbalance, frame_ms;
};
void write_comparison_svg(const std::string& path, const std::string& title,
                          const std::vector<ComparisonBar>& bars);

// View 0 of a frame with each pixel coloured by the device that rendered it; item borders
// darkened so tiles and strips are visible. Given the frame as rendered (same size), the
// colours are laid over it at 45% so the picture shows through.
void write_partition_png(const std::string& path, int width, int height,
                         const std::vector<std::vector<balance::WorkItem>>& rendered,
                         const Framebuffer* frame = nullptr);

// An SVG page around that PNG (referred to by its file name `png_name`, in the same
// folder): `title` above it (balancer and frame) and the device colours with `labels`.
void write_partition_svg(const std::string& path, const std::string& png_name,
                         const std::string& title, int width, int height,
                         const std::vector<std::string>& labels);

// One line of a scaling plot: (device count, efficiency) points.
struct ScalingSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;
};

// Efficiency (0..1) against device count (log2 axis), one line per series, with values.
void write_scaling_svg(const std::string& path, const std::string& title,
                       const std::vector<ScalingSeries>& series);

// The colour of device i in every plot.
const char* device_colour(size_t i);

}  // namespace multiray::study
