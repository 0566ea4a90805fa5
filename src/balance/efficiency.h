// Where a frame's time goes, and efficiency defined so that it cannot exceed 1 except by
// the error of the ideal's own measurement.
//
// Device i, timed alone on the whole frame, takes T_i (ms); its speed is s_i = 1 / T_i and
// the ideal frame time I = 1 / Σ s_i (every device busy on useful work until the same
// instant). In the run, the devices work in parallel for the phase's wall time W and each
// reports its own time t_i <= W. Weighting device i by its share of the ideal throughput,
// a_i = s_i · I (Σ a_i = 1), gives an exact identity, W = Σ a_i W:
//
//   W = I                          the ideal
//     + Σ a_i (W − t_i)            balance loss: devices idle, waiting for the last one
//     + Σ a_i stolen_i             stolen: the devices' threads runnable but not running
//                                  (their wall time minus their CPU time)
//     + Σ a_i t_i − I − stolen     per-item overhead: launches, pulls, small items, caches
//
// because Σ a_i (work share_i · T_i) = I Σ share_i = I whatever each device rendered. A
// frame's time is W plus the host's (planning, gathering and compositing, the balancer's
// update, an advisor's pre-pass); efficiency = I / (W + host). Balance loss, stolen and
// host are >= 0, so efficiency > 1 only when the overhead is negative, i.e. the devices
// together worked faster than when each was timed alone: the ideal's measurement error.
// Pure functions over plain values.
#pragma once

#include <string>
#include <vector>

namespace multiray::balance {

struct DeviceTiming {
  double alone_ms = 0;   // T_i: the whole frame rendered by this device alone (> 0)
  double time_ms = 0;    // t_i: its time in the frame (start to last item); 0 if dropped
  double stolen_ms = 0;  // its threads' wall time minus CPU time while rendering (>= 0)
};

// One frame's time in parts (ms). ideal + balance_loss + overhead + stolen + host = total
// exactly (rounding aside); valid is false when some alone time is not > 0 or the phase
// time is not finite and > 0.
struct Breakdown {
  double ideal = 0, balance_loss = 0, overhead = 0, stolen = 0, host = 0;
  double total = 0;  // phase + host
  bool valid = false;
  double efficiency() const { return valid && total > 0 ? ideal / total : 0; }
};

// `phase_ms`: W, the devices' wall time together; `host_ms`: the host's time around it.
// Device times above W (clock granularity) are taken as W, stolen time above t_i as t_i.
Breakdown break_down(const std::vector<DeviceTiming>& devices, double phase_ms, double host_ms);

// The element-wise mean of frames' breakdowns (the invalid ones left out): the parts of
// the mean still add up to the mean total. valid is false when none is valid.
Breakdown mean_breakdown(const std::vector<Breakdown>& frames);

// Why efficiency exceeds 1, in one sentence, or "" when it does not: the devices' work
// (time minus stolen time) was less than the ideal, so they ran faster in the frame than
// when they were timed alone.
std::string above_one_explanation(const Breakdown& b);

}  // namespace multiray::balance
