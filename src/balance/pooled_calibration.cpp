// calibrate_pooled() (trace_calibration.h): the calibration on several traces of the same
// devices and frames together, each device's fixed costs counted per take.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "balance/calibration_fit.h"
#include "balance/trace_calibration.h"
#include "balance/trace_takes.h"

namespace multiray::balance {

using calib::Obs;

namespace {

// A hypothesis flips only when it fits this much better (the 1/t-weighted residual).
constexpr double kBetter = 0.99;
// A batching device's fixed cost per frame inside its first take (an upload with the
// frame's first launch) is fitted only when it made at least this many first and this
// many later takes. (A device that does not batch pays its per-frame cost before its
// first item, in the gap; a first item's own fixed cost would only stand for the cost of
// the rows the first items render.)
constexpr int kMinTakes = 3;

using Bins = std::vector<std::pair<int, double>>;

struct Pooled {
  calib::Fit fit;
  std::vector<Obs> obs;
  std::vector<std::vector<std::pair<double, Bins>>> items;  // per observation: (time, bins)
  std::vector<int> takes, rendered;                         // per device
  double residual = 0;
};

// Σ (t − model)² / t over the items: a take's model time shared by the model costs of its
// items (as the simulator shares a launch's time), so that taking items together is
// judged on how the items' times fall, not only on their sums.
double item_residual(const Pooled& p) {
  double sum = 0;
  for (size_t j = 0; j < p.obs.size(); ++j) {
    const Obs& o = p.obs[j];
    double fixed = 0, total = 0;
    for (size_t u : o.fixed) fixed += p.fit.fixed[u];
    std::vector<double> cost;
    for (const auto& [t, bins] : p.items[j]) total += cost.emplace_back(p.fit.cost(o.frame, bins));
    const double take = fixed + p.fit.slow(o.busy) * total / p.fit.speed[o.device];
    for (size_t k = 0; k < cost.size(); ++k) {
      const double t = p.items[j][k].first;
      const double share = total > 0 ? cost[k] / total : 1.0 / double(cost.size());
      if (t > 0) sum += (t - take * share) * (t - take * share) / t;
    }
  }
  return sum;
}

// Every trace's takes as observations (fixed cost d per take, n + d per frame in the
// first take), frame by frame (the fit needs them ordered by frame), and the fit.
Pooled fit_takes(const std::vector<const Trace*>& traces,
                 const std::vector<calib::Origins>& origins, const std::vector<bool>& batching,
                 size_t from, double contention) {
  const size_t n = traces[0]->devices.size(), frames = traces[0]->frames.size();
  Pooled p;
  p.takes.assign(n, 0), p.rendered.assign(n, 0);
  std::vector<std::vector<calib::Take>> takes;
  std::vector<int> firsts(n, 0), laters(n, 0);
  for (size_t r = 0; r < traces.size(); ++r) {
    takes.push_back(calib::takes_of(*traces[r], origins[r], batching, from));
    for (const calib::Take& t : takes.back()) ++(t.first ? firsts : laters)[t.device];
  }
  for (size_t r = 0; r < traces.size(); ++r)
    for (const calib::Take& t : takes[r]) {
      const FrameStats& fs = traces[r]->frames[t.frame];
      Obs o{t.device, t.frame, r, 0, t.busy, {}, {t.device}};
      std::vector<std::pair<double, Bins>> items;
      for (size_t k = t.begin; k < t.end; ++k) {
        const ItemReport& item = fs.devices[t.device].items[k];
        o.time += item.time_ms;
        items.emplace_back(item.time_ms, calib::bins_of(item, fs.shape));
        calib::add_bins(o.bins, items.back().second);
      }
      if (t.first && batching[t.device] && firsts[t.device] >= kMinTakes &&
          laters[t.device] >= kMinTakes)
        o.fixed.push_back(n + t.device);
      ++p.takes[t.device];
      p.rendered[t.device] += int(t.end - t.begin);
      p.obs.push_back(std::move(o));
      p.items.push_back(std::move(items));
    }
  std::vector<size_t> order(p.obs.size());
  for (size_t j = 0; j < order.size(); ++j) order[j] = j;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return p.obs[a].frame < p.obs[b].frame; });
  std::vector<Obs> obs;
  std::vector<std::vector<std::pair<double, Bins>>> items;
  for (size_t j : order)
    obs.push_back(std::move(p.obs[j])), items.push_back(std::move(p.items[j]));
  p.obs = std::move(obs), p.items = std::move(items);
  p.fit = calib::fit_observations(p.obs, n, 2 * n, frames, traces.size(), contention);
  p.residual = item_residual(p);
  return p;
}

// Whether device d took two own items in a row anywhere (else batching changes nothing
// in the data and cannot be told).
bool can_batch(const std::vector<const Trace*>& traces, const std::vector<calib::Origins>& origins,
               size_t d, size_t from) {
  std::vector<bool> only(traces[0]->devices.size(), false);
  only[d] = true;
  for (size_t r = 0; r < traces.size(); ++r)
    for (const calib::Take& t : calib::takes_of(*traces[r], origins[r], only, from))
      if (t.device == d && t.end - t.begin >= 2) return true;
  return false;
}

// Whether device d's own items show launches: the engine shares a launch's time over its
// items by their samples, so two own items in a row of different sizes with one time per
// sample (to kSameRate) were rendered in one launch; items taken one by one differ by
// their fixed cost. (The simulator shares by cost: its traces show it only where cost
// per sample is flat, and a device without fixed costs on a flat cost looks batching.)
constexpr double kSameRate = 1e-9, kSameSize = 0.01;
bool shows_launches(const std::vector<const Trace*>& traces,
                    const std::vector<calib::Origins>& origins, size_t d, size_t from) {
  for (size_t r = 0; r < traces.size(); ++r)
    for (size_t f = from; f < traces[r]->frames.size(); ++f) {
      const std::vector<ItemReport>& items = traces[r]->frames[f].devices[d].items;
      const std::vector<bool>& own = origins[r].own[f][d];
      for (size_t k = 1; k < items.size(); ++k) {
        const ItemReport &a = items[k - 1], &b = items[k];
        if (!own[k - 1] || !own[k] || !(a.samples > 0) || !(b.samples > 0) || !(a.time_ms > 0) ||
            !(std::abs(a.samples / b.samples - 1) > kSameSize))
          continue;
        const double ra = a.time_ms / a.samples, rb = b.time_ms / b.samples;
        if (std::abs(rb / ra - 1) < kSameRate) return true;
      }
    }
  return false;
}

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

std::string trace_mismatch(const Trace& ref, const Trace& other, const std::string& ref_name) {
  if (other.devices.size() != ref.devices.size())
    return "has " + std::to_string(other.devices.size()) + " devices, " + ref_name + " " +
           std::to_string(ref.devices.size());
  for (size_t d = 0; d < ref.devices.size(); ++d) {
    const TraceDevice &a = ref.devices[d], &b = other.devices[d];
    if (b.name != a.name)
      return "has device " + std::to_string(d) + " '" + b.name + "', " + ref_name + " '" + a.name +
             "'";
    if (b.speed != a.speed)
      return "has device " + std::to_string(d) + " at emulated speed " + number(b.speed) + ", " +
             ref_name + " at " + number(a.speed);
  }
  if (other.frames.size() != ref.frames.size())
    return "has " + std::to_string(other.frames.size()) + " frames, " + ref_name + " " +
           std::to_string(ref.frames.size());
  for (size_t f = 0; f < ref.frames.size(); ++f) {
    const FrameShape &a = ref.frames[f].shape, &b = other.frames[f].shape;
    if (!a.same_size(b))
      return "has frames of " + std::to_string(b.width) + "x" + std::to_string(b.height) + " x " +
             std::to_string(b.views) + " views, " + ref_name + " " + std::to_string(a.width) +
             "x" + std::to_string(a.height) + " x " + std::to_string(a.views);
  }
  return "";
}

TraceCalibration calibrate_pooled(const std::vector<const Trace*>& traces, int warmup,
                                  double contention) {
  if (traces.empty()) throw std::invalid_argument("no trace to calibrate on");
  for (size_t r = 1; r < traces.size(); ++r) {
    const std::string why = trace_mismatch(*traces[0], *traces[r], "the first");
    if (!why.empty()) throw std::invalid_argument("trace " + std::to_string(r + 1) + " " + why);
  }
  const size_t from = size_t(std::max(warmup, 0));
  if (from >= traces[0]->frames.size())
    throw std::invalid_argument("the traces have no frames after the warm-up");
  const size_t n = traces[0]->devices.size();
  TraceCalibration cal;
  cal.pooled = true;
  cal.traces = int(traces.size());
  cal.frames = int(traces[0]->frames.size() - from);
  std::vector<calib::Origins> origins;
  for (const Trace* t : traces) {
    origins.push_back(calib::item_origins(*t));
    cal.plans_matched += origins.back().matched;
    cal.plans += int(t->frames.size());
  }
  // Batching: where the items show launches, so; else first as the balancers' own models
  // say (a launch inside the items), then the other way where the items can tell and fit
  // clearly better so.
  std::vector<bool> batching(n, false), shown(n, false);
  for (size_t d = 0; d < n; ++d) {
    shown[d] = batching[d] = shows_launches(traces, origins, d, from);
    for (const Trace* t : traces) batching[d] = batching[d] || calib::launch_of(*t, from, d) > 0;
  }
  Pooled best = fit_takes(traces, origins, batching, from, contention);
  for (size_t d = 0; d < n; ++d) {
    if (shown[d] || !can_batch(traces, origins, d, from)) continue;
    std::vector<bool> other = batching;
    other[d] = !other[d];
    Pooled p = fit_takes(traces, origins, other, from, contention);
    if (p.residual < kBetter * best.residual) best = std::move(p), batching = other;
  }
  const calib::Fit& s = best.fit;
  cal.contention = s.contention;
  cal.contention_identified = s.contention_identified;
  cal.alone_share = s.alone_share;
  cal.frame_noise = s.frame_noise;
  cal.devices.resize(n);
  for (size_t d = 0; d < n; ++d) {
    CalibratedDevice& dev = cal.devices[d];
    dev.speed = s.speed[d];
    dev.batching = batching[d];
    (batching[d] ? dev.launch_ms : dev.item_overhead_ms) = s.fixed[d];
    dev.overhead_fitted = s.fitted[d];
    dev.first_take_ms = s.fixed[n + d];
    dev.first_take_fitted = s.fitted[n + d];
    dev.items = best.rendered[d];
    dev.takes = best.takes[d];
    std::vector<double> times, gaps;
    for (const Trace* t : traces) calib::frame_times(*t, from, d, times, gaps);
    dev.frame_overhead_ms = calib::median(gaps) + dev.first_take_ms;
  }
  return cal;
}

}  // namespace multiray::balance
