// What the devices measured in one frame, and the balance metrics derived from it.
#pragma once

#include <cstdint>
#include <vector>

#include "balance/plan.h"

namespace multiray::balance {

// ItemReport (one item as a device rendered it) is util/rect.h's, through partition/rect.h.

struct DeviceFrameStats {
  double time_ms = 0;  // time the device worked on this frame (busy + emulated idle): the
                       // quantity balancers equalise
  double busy_ms = 0;  // pure compute time
  double samples = 0, pixels = 0;
  std::vector<ItemReport> items;  // what it actually rendered, incl. pulled and stolen items
  bool alive = true;              // false: the device died; balancers drop it
  bool rested = false;  // left out of the frame by its plan (Plan::resting): no measurement
};

struct FrameStats {
  int frame = 0;
  FrameShape shape;
  std::vector<DeviceFrameStats> devices;
};

// Balance metrics over the alive devices that took part (not rested) whose time is finite
// and >= 0 (see DESIGN.md).
// Frame time: the largest device time (ms); 0 when no device qualifies.
double frame_time_ms(const FrameStats& stats);
// Imbalance λ = t_max / t_mean − 1; 0 with fewer than one usable device or a zero mean.
double imbalance(const FrameStats& stats);
// Deviation (Harada) = max_i |t_i − t_mean| / t_mean; 0 as above.
double deviation(const FrameStats& stats);
// The same two over plain times (ms; entries not finite or < 0 left out): the one
// definition the engine's frame records, the bench and the simulator use.
double imbalance(const std::vector<double>& times);
double deviation(const std::vector<double>& times);

// The imbalance under which a frame counts as balanced when recovery is measured.
inline constexpr double kRecoveredImbalance = 0.05;

// Recovery after a change that takes effect at frame `from` (one definition for the bench,
// the docs and the tests): the first frame f >= `from` from which the imbalance stays
// below `limit` to the end of the run, i.e. imbalance[g] < limit for every g in [f, end).
// `imbalance` is indexed by frame. -1 when the last frame is not below `limit` or `from`
// is not a frame of the run.
int recovered_from(const std::vector<double>& imbalance, int from,
                   double limit = kRecoveredImbalance);

}  // namespace multiray::balance
