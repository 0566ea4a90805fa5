// hybrid's learning from each frame's measurements (hybrid.h describes the model):
// speeds with their noise and change detection, the fixed cost per item and per frame,
// and the cost of each row. The planning is in hybrid.cpp.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "balance/hybrid.h"
#include "balance/line_density.h"

namespace multiray::balance {
double HybridBalancer::noise(size_t i) const {
  return noise_weight_[i] > 0 ? std::sqrt(noise_sum_[i] / noise_weight_[i]) : 0.0;
}

std::vector<double> HybridBalancer::noise() const {
  std::vector<double> sigma(speed_.size());
  for (size_t i = 0; i < sigma.size(); ++i) sigma[i] = noise(i);
  return sigma;
}

bool HybridBalancer::jumps(size_t i, double m) const {
  const double s = speed_[i];
  if (!opt_.detect_noise || noise_count_[i] < kMinHistory) return std::abs(m / s - 1) > opt_.jump;
  return std::abs(std::log(m / s)) > std::max(opt_.z * noise(i), kNoiseFloor);
}

void HybridBalancer::take_speed(size_t i, double m) {
  double& s = speed_[i];
  if (!(s > 0)) {  // the first measurement
    s = m;
    return;
  }
  bool change = jumps(i, m);
  int beyond = 0;  // the side of a measurement beyond the confirmation bound
  if (opt_.detect_noise && noise_count_[i] >= kMinHistory) {
    const double bound = std::max(kConfirmSigmas * noise(i), kNoiseFloor);
    const double r = std::log(m / s), r0 = std::log(m / pending_base_[i]);
    if (!change && pending_[i] != 0 && std::abs(r0) > bound && (r0 > 0 ? 1 : -1) == pending_[i]) {
      // The second measurement in a row beyond the bound on the same side of the estimate
      // both were made against: a change that began with the first, which therefore
      // leaves the noise history again.
      change = true;
      noise_sum_[i] = undo_sum_[i], noise_weight_[i] = undo_weight_[i], --noise_count_[i];
    }
    if (std::abs(r) > bound) beyond = r > 0 ? 1 : -1;
  }
  if (change) {
    s = m;
    pending_[i] = 0;
    ++changes_[i];
    return;
  }
  if (opt_.detect_noise) {
    const double r = std::log(m / s);
    undo_sum_[i] = noise_sum_[i], undo_weight_[i] = noise_weight_[i];
    noise_sum_[i] = (1 - kNoiseWeight) * noise_sum_[i] + kNoiseWeight * r * r;
    noise_weight_[i] = (1 - kNoiseWeight) * noise_weight_[i] + kNoiseWeight;
    ++noise_count_[i];
    pending_[i] = beyond;
    pending_base_[i] = s;
  }
  s = (1 - opt_.alpha) * s + opt_.alpha * m;
}

void HybridBalancer::restate_left_out(const std::vector<double>& jumps) {
  if (jumps.empty()) return;
  double log_sum = 0;
  for (double r : jumps) log_sum += std::log(r);
  const double r = std::exp(log_sum / double(jumps.size()));  // their geometric mean
  // Smaller jumps are the noise and drift of a busy device (PoCL's frames vary by 1.5x
  // along an orbit): each would cost a probe's frame. Left-out devices still meet such
  // drifts at their scheduled probes.
  if (std::abs(std::log(r)) < std::log(kRestateJump)) return;
  for (int i = 0; i < device_count(); ++i)
    if (part_.left_out(size_t(i)) && !probing_[size_t(i)]) {
      if (speed_[size_t(i)] > 0) speed_[size_t(i)] *= r;
      part_.rescale(size_t(i), r);
    }
  part_.changed(false);
}

void HybridBalancer::take_frame_cost(size_t i, const DeviceFrameStats& d) {
  if (!opt_.frame_cost || d.items.empty()) return;
  double items = 0;
  for (const ItemReport& r : d.items) {
    if (!valid_time(r.time_ms)) return;  // an unusable item time: no gap to measure
    items += r.time_ms;
  }
  const double gap = std::max(d.time_ms - items, 0.0);
  if (!std::isfinite(gap)) return;
  double& f = frame_cost_[i];
  f = frame_seen_[i] ? (1 - kFrameCostWeight) * f + kFrameCostWeight * gap : gap;
  frame_seen_[i] = true;
}

namespace {

// Intercept of the least-squares line t = o + c/s through (cost, time) pairs, weighted by
// 1/cost, and its variance (from the residuals). False when there are fewer than 3 usable
// pairs, the costs differ by less than 2x, or the slope is not positive.
bool fixed_cost_fit(const std::vector<std::pair<double, double>>& points, double& intercept,
                    double& variance) {
  double w = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, lo = std::numeric_limits<double>::infinity(),
         hi = 0;
  int count = 0;
  auto usable = [](double c, double t) { return c > 0 && std::isfinite(c) && valid_time(t); };
  for (const auto& [c, t] : points) {
    if (!usable(c, t)) continue;
    const double wi = 1 / c;
    w += wi, sx += wi * c, sy += wi * t, sxx += wi * c * c, sxy += wi * c * t;
    lo = std::min(lo, c), hi = std::max(hi, c), ++count;
  }
  if (count < 3 || !(hi >= 2 * lo)) return false;
  const double det = w * sxx - sx * sx;
  if (!(det > 0) || !std::isfinite(det)) return false;
  const double slope = (w * sxy - sx * sy) / det;
  if (!(slope > 0) || !std::isfinite(slope)) return false;
  intercept = (sy - slope * sx) / w;
  double residual = 0;
  for (const auto& [c, t] : points)
    if (usable(c, t)) residual += std::pow(t - intercept - slope * c, 2) / c;
  variance = residual / (count - 2) * sxx / det;
  return std::isfinite(intercept) && std::isfinite(variance);
}

}  // namespace

void HybridBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  const FrameShape& shape = stats.shape;
  if (alive_count() == 0 || shape.pixels() == 0) return;
  // A report for another size than the last plan (a foreign or stale report) still
  // measures speeds, at mean cost 1, but teaches nothing about this frame's rows.
  const bool own_shape = cost_shape_.same_size(shape);
  WeightMap base;
  try {
    base = WeightMap(shape.width, shape.height, shape.views, shape.pixel_weight);
  } catch (const std::invalid_argument&) {
    base = WeightMap(shape.width, shape.height, shape.views, {});
  }
  // Model cost of an item: Σ over its rows of base weight × k(row).
  auto model_cost = [&](const WorkItem& item) {
    if (!own_shape) return base.sum(item);
    double c = 0;
    if (item.view < 0 || item.view >= shape.views) return c;
    for (int y = std::max(item.rect.y0, 0); y < std::min(item.rect.y1, shape.height); ++y)
      c += base.sum(WorkItem{Rect{item.rect.x0, y, item.rect.x1, y + 1}, item.view}) *
           cost_[size_t(item.view) * size_t(shape.height) + size_t(y)];
    return c;
  };

  LineDensity observed(base);
  std::vector<std::pair<double, double>> points;  // (model cost, time) of each item
  std::vector<double> jumps;  // speed ratios of the devices taking part that jumped
  // Who was started this frame, and each one's measured speed: the samples of contention.
  std::vector<bool> took(size_t(device_count()), false);
  std::vector<double> measured_speed(size_t(device_count()), 0.0);
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || d->rested || !valid_time(d->time_ms)) continue;
    took[size_t(i)] = true;
    double work = 0;
    points.clear();
    for (const ItemReport& r : d->items) {
      points.push_back({model_cost(r.item), r.time_ms});
      work += points.back().first;
    }
    if (d->items.empty()) work = work_done(*d);  // no item reports: assume mean cost 1
    // Its frame fit takes a frame of no work too (everything stolen from it while it was
    // starting): that is its fixed cost, measured alone.
    part_.measured(size_t(i), work, d->time_ms);
    if (!(work > 0) || !std::isfinite(work)) continue;
    // The fixed cost per item, and the device's time net of it. Each frame's fit counts by
    // its precision (1/variance; a fit on a few items under outside load is worth little
    // next to one on many), older fits fading by kOverheadMemory a frame. A speed that changed
    // during the frame makes the last (small) items look dear, as a fixed cost would: the
    // fit is only taken when the speed measured with the current fixed cost is no jump.
    take_frame_cost(size_t(i), *d);
    const double items = double(d->items.size());
    const double f = frame_cost_[size_t(i)];
    double& o = overhead_[size_t(i)];
    const double s = speed_[size_t(i)];
    const double mean_item = (d->time_ms - f) / items;
    // (With `jump` in either mode: this gate is for gross changes inside the frame. The
    // noise rule would also shut out the frames whose speed moves by a few percent because
    // o_i is still being learnt, and o_i would never be.)
    const bool steady =
        !(s > 0) || std::abs(work / std::max(d->time_ms - f - items * o, 0.5 * d->time_ms) / s -
                             1) <= opt_.jump;
    double fit = 0, variance = 0;
    bool timed = false;  // some item has a usable time
    for (const ItemReport& r : d->items) timed |= valid_time(r.time_ms);
    if (opt_.overhead > 0 && own_shape && timed) {
      double& sum = overhead_sum_[size_t(i)];
      double& weights = overhead_weight_[size_t(i)];
      sum *= kOverheadMemory, weights *= kOverheadMemory;  // earlier fits age, fit or not
      if (steady && fixed_cost_fit(points, fit, variance)) {
        const double weight = 1 / (variance + std::pow(1e-3 * mean_item, 2));
        sum += weight * std::clamp(fit, -0.5 * mean_item, 0.5 * mean_item);
        weights += weight;
      }
      // Two standard errors below the mean: errors in the model costs bias the intercept
      // upwards, so only what the frames show clearly counts (and aged evidence fades).
      const double clear = sum / weights - 2 / std::sqrt(weights);
      o = std::isfinite(clear) ? std::clamp(clear, 0.0, 0.5 * mean_item) : 0.0;
    }
    const double net = std::max(d->time_ms - f - items * o, 0.5 * d->time_ms);
    const double measured = work / net;
    measured_speed[size_t(i)] = measured;
    const int changes = changes_[size_t(i)];
    const double before = speed_[size_t(i)];
    take_speed(size_t(i), measured);
    // A device taking part (not a probe) whose speed jumped says the cost of work may
    // have changed (spp, scene): the left-out devices, which did not see it, are restated
    // and probed. (Its own fit is not: a device with a hidden fixed cost jumps when its
    // share changes, and its frames show the fixed cost as it is.)
    if (changes_[size_t(i)] != changes && before > 0 && !probing_[size_t(i)])
      jumps.push_back(speed_[size_t(i)] / before);
    // Each item's time net of the fixed cost, as a share of the device's work: its
    // observed cost (so emulated idle, if the engine reports it only per frame, is
    // spread over the items).
    if (!own_shape) continue;
    double item_time = 0;
    for (const ItemReport& r : d->items)
      if (valid_time(r.time_ms)) item_time += std::max(r.time_ms - o, 0.0);
    if (!(item_time > 0)) continue;
    const double scale = net / item_time * measured;
    for (const ItemReport& r : d->items)
      if (valid_time(r.time_ms)) observed.add(r.item, std::max(r.time_ms - o, 0.0) * scale);
  }
  // A probe perturbs the devices taking part (it shares their caches, memory and cores):
  // their jumps in a probe's frame and in the frame after it (the way back) are not a
  // change of the cost of work, and would only probe again.
  bool probed = false;
  for (bool p : probing_) probed |= p;
  frames_since_probe_ = probed ? 0 : frames_since_probe_ + 1;
  part_.frame_speeds(took, measured_speed, frames_since_probe_ >= 2);
  if (frames_since_probe_ >= 2) restate_left_out(jumps);
  if (observed.empty()) return;

  const std::vector<double> fresh = observed.density(std::numeric_limits<double>::quiet_NaN());
  const std::vector<double> row_base = flat_row_weights(base);
  double weighted = 0, base_sum = 0;
  for (size_t c = 0; c < cost_.size(); ++c) {
    if (std::isfinite(fresh[c])) cost_[c] = (1 - opt_.gamma) * cost_[c] + opt_.gamma * fresh[c];
    weighted += row_base[c] * cost_[c];
    base_sum += row_base[c];
  }
  // Keep k at mean 1 (costs and speeds scale together, so the plan is unchanged).
  const double f = weighted / base_sum;
  if (!(f > 0) || !std::isfinite(f)) return;
  // Clamped so one absurd report cannot make a row free or infinitely dear.
  for (double& k : cost_) k = std::clamp(k / f, 1e-3, 1e3);
  for (double& s : speed_) s /= f;
}

}  // namespace multiray::balance
