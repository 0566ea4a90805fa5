// Calibration of the simulator from a trace (docs/traces.md, "Calibration"): what the
// devices that recorded it cost beyond the work itself — a fixed cost per item, a fixed
// cost per frame, their slowing each other down while both run — and their speeds
// relative to each other, so that the trace replayed with another balancer predicts what
// that balancer does on the same devices.
#pragma once

#include <string>
#include <vector>

#include "balance/simulate.h"
#include "balance/trace.h"

namespace multiray::balance {

struct CalibratedDevice {
  double speed = 1;             // rendering alone, relative to the fastest device (1)
  double item_overhead_ms = 0;  // fixed cost per item, o_i (0 when not fitted)
  double frame_overhead_ms =
      0;  // fixed cost per frame, f_i: median of time − Σ items (+ first_take_ms)
  bool overhead_fitted = false;  // false: too few items, or sizes too alike, to fit o_i
  // Fixed cost per launch inside the device's items (a batching OpenCL device spreads its
  // launch over the items it took together; SimDevice::launch_ms). The item fit cannot
  // see it when the device rendered few items; it is taken from the balancer's own model
  // of the device (the trace's `model` records, participation.h) when that model
  // determined a fixed cost per frame, clear of noise, that the frame's gaps do not hold.
  double launch_ms = 0;
  int items = 0;  // items the fit saw
  // calibrate_pooled() only. The device takes its own list's remaining items in one
  // launch (then launch_ms is its fixed cost per take and item_overhead_ms 0; else
  // item_overhead_ms is, and each item is a take): chosen by which fits the items better.
  bool batching = false;
  // The part of frame_overhead_ms paid inside the device's first take of a frame (not in
  // a gap before it): seen where the device made several takes in a frame.
  double first_take_ms = 0;
  bool first_take_fitted = false;
  int takes = 0;  // takes the fit saw (items rendered in one launch count once)
};

struct TraceCalibration {
  std::vector<CalibratedDevice> devices;
  // While k devices are at work each runs 1 + contention·(k − 1) times slower
  // (SimDevice::contention). Identified only when items ran alone (another device had
  // run out of work) on at least kMinAloneShare of some device's cost; else as given. At most 1.
  double contention = 0;
  bool contention_identified = false;
  double alone_share = 0;  // share of all the cost rendered by a device working alone
  // Per-frame speed noise, the half-width x of a uniform 1 + U(−x, x) common to all
  // devices (SimDevice::frame_noise), from how each device's speed varies frame to frame.
  double frame_noise = 0;
  int frames = 0;  // frames calibrated on (per trace)
  // calibrate_pooled(): on how many traces, and in how many of their frames the balancer
  // replayed on the recorded frames made the plan recorded (which tells own items from
  // pulled and stolen ones; other frames fall back on the item ids).
  bool pooled = false;
  int traces = 1;
  int plans_matched = 0, plans = 0;
};

inline constexpr double kMinAloneShare = 0.03;

// Calibrates on frames `warmup` and later of `trace` (a pure function of the trace). Per
// device: an item of samples w in a frame of mean net cost per sample D (ms at speed 1)
// has model cost c = w·D; its time is t = o_i + c·(1 + contention·(k − 1))/s_i, k the
// devices at work when it started (its start: the device's frame overhead, then its
// earlier items back to back). o_i and 1/s_i are the intercept and slope of
// fixed_cost_fit(); D is recomputed from the net item costs, and the fit repeated, until
// they settle. `contention` < 0: learn it (0 when not identifiable); >= 0: use it as is.
// Throws std::invalid_argument when no frame is left after the warm-up.
TraceCalibration calibrate(const Trace& trace, int warmup = 0, double contention = -1);

// One simulated device per calibrated one: its speed, fixed costs and the contention
// (frame noise `noise`, default none: the recorded costs carry the recorded noise).
std::vector<SimDevice> calibrated_devices(const TraceCalibration& cal, double noise = 0);

// `trace` with every item's time net of what the calibration puts outside the work —
// (t − o_i) / (1 + contention·(k − 1)) — and the calibrated speeds, so that trace_cost()
// and replay_trace() of it give the work alone (the fixed costs and contention are the
// simulated devices' part, not counted twice).
// With a pooled calibration the fixed cost of each take (and a first take's share of
// the frame's) is taken out of its items in proportion to their times.
Trace net_trace(const Trace& trace, const TraceCalibration& cal);

// "" when `other` may be calibrated on or predicted with `ref`: the same devices (names
// and emulated speeds), frame count and frame sizes; else one line on the first
// difference, "has 3 devices, <ref_name> 2".
std::string trace_mismatch(const Trace& ref, const Trace& other, const std::string& ref_name);

// Calibrates on frames `warmup` and later of several traces of the same devices and
// frames (one bench run's lanes: other balancers) together: each frame's cost map is
// shared by every trace's items of that frame, and each device's speed, fixed cost per
// take (an item, or a launch of its own list for a batching device), fixed cost per frame
// and the contention are fitted on all of them (docs/traces.md, "Pooled calibration"). A
// slow device that one balancer gave a few items is then seen in the traces of the
// others. Which items a device took together comes from each trace's plans, made again
// by its balancer (item_origins()). Throws std::invalid_argument when `traces` is empty,
// two of them do not match (trace_mismatch()) or no frame is left after the warm-up.
TraceCalibration calibrate_pooled(const std::vector<const Trace*>& traces, int warmup = 0,
                                  double contention = -1);

// The cost to replay with a pooled calibration: every frame's net cost density pooled
// over `traces` (each trace's net_trace(), cut along every item edge of any of them; per
// piece, the mean of the traces' densities weighted by their precision, (area / (t·s))²
// for an item of recorded time t on a device of speed s). Device 0 holds every piece,
// every device at speed 1; the frames are those of traces[0]. Throws as calibrate_pooled().
Trace pooled_costs(const std::vector<const Trace*>& traces, const TraceCalibration& cal);

}  // namespace multiray::balance
