// Pictures for people: per-balancer timing plots (SVG) and partition images (PNG).
#pragma once

#include <string>
#include <vector>

#include "balance/plan.h"
#include "engine/frame_record.h"

namespace multiray::app {

// Per-device time per frame (lines, top) and work shares stacked beneath (bottom).
// `labels` name the devices (emulated ones should say so).
void write_timeline_svg(const std::string& path, const std::string& title,
                        const std::vector<FrameRecord>& frames,
                        const std::vector<std::string>& labels);

// View 0 of a frame with each pixel coloured by the device that rendered it; item borders
// darkened so tiles and strips are visible.
void write_partition_png(const std::string& path, int width, int height,
                         const std::vector<std::vector<balance::WorkItem>>& rendered);

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

}  // namespace multiray::app
