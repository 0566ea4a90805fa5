#include "balance/trace_calibration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "balance/calibration_fit.h"
#include "balance/trace_takes.h"

namespace multiray::balance {

using calib::Obs;

namespace {

// Items of frames `from` on, with the devices at work at each one's start: a device's
// items run back to back after its frame overhead (time − Σ items), and a device is at
// work until its frame time (as SimDevice::contention counts). A device's launch cost
// `launch[d]` is taken out of its items in proportion to their times (as the OpenCL
// device apportions a launch), one launch per frame.
std::vector<Obs> items_of(const Trace& trace, size_t from, const std::vector<double>& launch) {
  std::vector<Obs> out;
  for (size_t f = from; f < trace.frames.size(); ++f) {
    const FrameStats& fs = trace.frames[f];
    for (size_t d = 0; d < fs.devices.size(); ++d) {
      const DeviceFrameStats& dev = fs.devices[d];
      double sum = 0;
      for (const ItemReport& r : dev.items) sum += r.time_ms;
      const double keep = launch[d] > 0 && sum > 0 ? std::max(sum - launch[d], 0.0) / sum : 1.0;
      double start = std::max(dev.time_ms - sum, 0.0);
      for (const ItemReport& r : dev.items) {
        int busy = 0;
        for (const DeviceFrameStats& other : fs.devices)
          busy += other.alive && !other.items.empty() && other.time_ms > start;
        out.push_back(
            {d, f, 0, r.time_ms * keep, std::max(busy, 1), calib::bins_of(r, fs.shape), {d}});
        start += r.time_ms;
      }
    }
  }
  return out;
}

}  // namespace

namespace calib {

void frame_times(const Trace& trace, size_t from, size_t d, std::vector<double>& times,
                 std::vector<double>& gaps) {
  for (size_t f = from; f < trace.frames.size(); ++f) {
    const DeviceFrameStats& fd = trace.frames[f].devices[d];
    if (fd.items.empty()) continue;
    double sum = 0;
    for (const ItemReport& r : fd.items) sum += r.time_ms;
    times.push_back(fd.time_ms);
    gaps.push_back(std::max(fd.time_ms - sum, 0.0));
  }
}

// The launch cost inside device d's items, from the balancer's last determined model of
// it (frames `from` on): its fixed cost per frame F when F is clear of noise (over two
// standard errors), at least kLaunchShare of the device's median frame, and not in the
// gaps between its items (median gap under F / 2); F less that gap. Else 0.
constexpr double kLaunchShare = 0.05;
double launch_of(const Trace& trace, size_t from, size_t d) {
  const DeviceCostModel* last = nullptr;
  for (size_t f = from; f < trace.models.size(); ++f)
    if (d < trace.models[f].size() && trace.models[f][d].determined) last = &trace.models[f][d];
  if (!last || !(last->fixed_ms > 2 * last->fixed_sigma) || !(last->fixed_ms > 0)) return 0;
  std::vector<double> times, gaps;
  frame_times(trace, from, d, times, gaps);
  const double gap = median(gaps);
  if (times.empty() || !(last->fixed_ms >= kLaunchShare * median(times)) ||
      !(gap < last->fixed_ms / 2))
    return 0;
  return last->fixed_ms - gap;
}

}  // namespace calib

TraceCalibration calibrate(const Trace& trace, int warmup, double contention) {
  const size_t from = size_t(std::max(warmup, 0));
  if (from >= trace.frames.size())
    throw std::invalid_argument("the trace has no frames after the warm-up");
  const size_t n = trace.devices.size(), frames = trace.frames.size();
  TraceCalibration cal;
  cal.devices.resize(n);
  cal.frames = int(frames - from);
  std::vector<double> launch(n, 0.0);
  for (size_t d = 0; d < n; ++d) launch[d] = calib::launch_of(trace, from, d);
  const std::vector<Obs> items = items_of(trace, from, launch);
  const calib::Fit s = calib::fit_observations(items, n, n, frames, 1, contention);
  cal.contention = s.contention;
  cal.contention_identified = s.contention_identified;
  cal.alone_share = s.alone_share;
  cal.frame_noise = s.frame_noise;
  for (size_t d = 0; d < n; ++d) {
    CalibratedDevice& dev = cal.devices[d];
    dev.speed = s.speed[d];
    dev.item_overhead_ms = s.fixed[d];
    dev.overhead_fitted = s.fitted[d];
    dev.launch_ms = launch[d];
    std::vector<double> times, gaps;
    calib::frame_times(trace, from, d, times, gaps);
    for (const Obs& it : items) dev.items += it.device == d;
    dev.frame_overhead_ms = calib::median(gaps);
  }
  return cal;
}

std::vector<SimDevice> calibrated_devices(const TraceCalibration& cal, double noise) {
  std::vector<SimDevice> out;
  for (const CalibratedDevice& d : cal.devices) {
    SimDevice s;
    s.speed = d.speed;
    s.item_overhead_ms = d.item_overhead_ms;
    s.frame_overhead_ms = d.frame_overhead_ms;
    s.launch_ms = d.launch_ms;
    s.contention = cal.contention;
    s.frame_noise = noise;
    out.push_back(s);
  }
  return out;
}

Trace net_trace(const Trace& trace, const TraceCalibration& cal) {
  if (cal.pooled) {
    std::vector<bool> batching;
    std::vector<double> per_take, first_take;
    for (const CalibratedDevice& d : cal.devices) {
      batching.push_back(d.batching);
      per_take.push_back(d.item_overhead_ms + d.launch_ms);
      first_take.push_back(d.first_take_ms);
    }
    Trace out = calib::net_trace_takes(trace, batching, per_take, first_take, cal.contention);
    for (size_t d = 0; d < out.devices.size(); ++d) out.devices[d].speed = cal.devices[d].speed;
    return out;
  }
  Trace out = trace;
  for (size_t d = 0; d < out.devices.size(); ++d) out.devices[d].speed = cal.devices[d].speed;
  calib::Fit s;
  s.speed.assign(cal.devices.size(), 1.0);
  s.contention = cal.contention;
  std::vector<double> launch;
  for (const CalibratedDevice& d : cal.devices) {
    s.fixed.push_back(d.item_overhead_ms);
    launch.push_back(d.launch_ms);
  }
  const std::vector<Obs> items = items_of(trace, 0, launch);
  size_t next = 0;  // items_of lists the items in the trace's order
  for (FrameStats& f : out.frames)
    for (DeviceFrameStats& dev : f.devices)
      for (ItemReport& r : dev.items) r.time_ms = r.busy_ms = s.net(items[next++]);
  return out;
}

}  // namespace multiray::balance
