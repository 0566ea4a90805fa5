// How the pooled calibration (trace_calibration.h) sees a device's launches: which items
// it rendered in one take. A batching device (SimDevice::launch_ms) takes its own list's
// remaining items with the first of them and pays one launch for all; an item pulled from
// the shared queue or stolen is a take of its own. Internal to the balance library.
#pragma once

#include <vector>

#include "balance/trace.h"

namespace multiray::balance::calib {

// Per frame, device and item of `trace` (in the order rendered): true when the item came
// from the device's own list in the plan the trace's balancer makes for that frame when
// fed the recorded frames before it (as the engine fed it), false when it was pulled
// from the shared queue or stolen. A frame whose plan does not hold every recorded item
// under its id (a balancer that no longer plans so, pixel weights the trace does not
// keep) falls back on the ids alone: a device's own items are the leading run of
// consecutive ids it rendered.
struct Origins {
  std::vector<std::vector<std::vector<bool>>> own;  // [frame][device][item]
  int matched = 0;                                  // frames whose plan held every item
};
Origins item_origins(const Trace& trace);

// One take: items [begin, end) of `device` in `frame`.
struct Take {
  size_t frame = 0, device = 0, begin = 0, end = 0;
  bool first = false;  // the device's first take of the frame
  int busy = 1;        // devices at work when it started, itself included
};

// The takes of frames `from` on: a batching device's consecutive own items make one take;
// any other item is a take of its own. A take starts after the device's frame overhead
// (time − Σ items) and its earlier items back to back; a device is at work until its
// frame time (as SimDevice::contention counts).
std::vector<Take> takes_of(const Trace& trace, const Origins& origins,
                           const std::vector<bool>& batching, size_t from);

// net_trace() for a pooled calibration: each take's fixed costs (per take, and the first
// take's share of the frame's) out of its items in proportion to their times, then the
// contention (trace_calibration.h).
Trace net_trace_takes(const Trace& trace, const std::vector<bool>& batching,
                      const std::vector<double>& per_take, const std::vector<double>& first_take,
                      double contention);

}  // namespace multiray::balance::calib
