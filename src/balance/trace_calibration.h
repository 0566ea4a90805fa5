// Calibration of the simulator from a trace (docs/traces.md, "Calibration"): what the
// devices that recorded it cost beyond the work itself — a fixed cost per item, a fixed
// cost per frame, their slowing each other down while both run — and their speeds
// relative to each other, so that the trace replayed with another balancer predicts what
// that balancer does on the same devices.
#pragma once

#include <vector>

#include "balance/simulate.h"
#include "balance/trace.h"

namespace multiray::balance {

struct CalibratedDevice {
  double speed = 1;              // rendering alone, relative to the fastest device (1)
  double item_overhead_ms = 0;   // fixed cost per item, o_i (0 when not fitted)
  double frame_overhead_ms = 0;  // fixed cost per frame, f_i: median of time − Σ items
  bool overhead_fitted = false;  // false: too few items, or sizes too alike, to fit o_i
  // Fixed cost per launch inside the device's items (a batching OpenCL device spreads its
  // launch over the items it took together; SimDevice::launch_ms). The item fit cannot
  // see it when the device rendered few items; it is taken from the balancer's own model
  // of the device (the trace's `model` records, participation.h) when that model
  // determined a fixed cost per frame, clear of noise, that the frame's gaps do not hold.
  double launch_ms = 0;
  int items = 0;  // items the fit saw
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
  int frames = 0;  // frames calibrated on
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
Trace net_trace(const Trace& trace, const TraceCalibration& cal);

}  // namespace multiray::balance
