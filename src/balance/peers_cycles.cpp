#include "balance/peers_cycles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

namespace multiray::balance {

std::vector<Rect> cycles_slices(int width, int height, const std::vector<double>& weights) {
  std::vector<Rect> out(weights.size());
  if (width <= 0 || height <= 0) return out;
  size_t last = weights.size();
  for (size_t i = 0; i < weights.size(); ++i)
    if (weights[i] > 0) last = i;
  int y = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!(weights[i] > 0)) continue;
    const int left = std::max(0, height - y);
    int rows = left;
    if (i != last) {
      const double want = std::round(double(height) * std::min(weights[i], 1.0));
      rows = std::min(std::max(int(want), 1), left);
    }
    out[i] = Rect{0, y, width, y + rows};
    y += rows;
  }
  return out;
}

CyclesBalancer::CyclesBalancer(int device_count, double interval_ms)
    : BalancerBase(device_count),
      interval_ms_(interval_ms),
      weights_(even()),
      time_spent_(size_t(device_count), 0.0) {}

std::string CyclesBalancer::spec() const {
  std::ostringstream s;
  s << "cycles:interval_ms=" << interval_ms_;
  return s.str();
}

void CyclesBalancer::on_drop(int index) {
  weights_[size_t(index)] = 0;
  weights_ = sanitize(weights_, even());
  std::fill(time_spent_.begin(), time_spent_.end(), 0.0);
  measured_ = false;  // rebalance after the next usable frame, as after Cycles' first work
  last_changed_ = false;
}

Plan CyclesBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  plan.ratios = sanitize(weights_, even());
  if (shape.pixels() == 0) return plan;
  const std::vector<Rect> slices = cycles_slices(shape.width, shape.height, plan.ratios);
  for (int view = 0; view < shape.views; ++view)
    for (size_t i = 0; i < slices.size(); ++i)
      if (!slices[i].empty()) plan.assigned[i].push_back(WorkItem{slices[i], view});
  return plan;
}

void CyclesBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  if (alive_count() == 0) return;
  // Cycles times every device on every work; a frame without that is not used at all.
  std::vector<double> spent = time_spent_;
  double frame_ms = 0;
  for (int i = 0; i < device_count(); ++i) {
    if (!alive(i)) continue;
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms)) return;
    spent[size_t(i)] += d->time_ms;
    if (!valid_time(spent[size_t(i)])) return;  // overflow
    frame_ms = std::max(frame_ms, d->time_ms);
  }
  time_spent_ = std::move(spent);
  clock_ms_ += frame_ms;

  bool due;
  if (!measured_) {  // Cycles' need_rebalance_at_next_work after the first work
    measured_ = true;
    due = true;
  } else {
    due = last_changed_ || clock_ms_ - last_rebalance_ms_ > interval_ms_;
  }
  if (!due) return;
  last_rebalance_ms_ = clock_ms_;
  ++requested_;
  last_changed_ = rebalance();
  if (last_changed_) ++changed_;
}

bool CyclesBalancer::rebalance() {
  const int n = alive_count();
  double total = 0;
  for (int i = 0; i < device_count(); ++i)
    if (alive(i)) total += time_spent_[size_t(i)];
  const double mean = total / n;
  if (!valid_time(mean)) return false;
  const double lerp = 1.0 / n;
  std::vector<double> next(weights_.size(), 0.0);
  double sum = 0;
  bool big_difference = false;
  for (int i = 0; i < device_count(); ++i) {
    if (!alive(i)) continue;
    const double t = time_spent_[size_t(i)];
    const double target = t + (mean - t) * lerp;
    next[size_t(i)] = weights_[size_t(i)] * (target / t);
    sum += next[size_t(i)];
    if (std::fabs(1.0 - target / mean) > 0.02) big_difference = true;
  }
  if (!big_difference) return false;
  if (!valid_time(sum)) return false;  // an extreme ratio of times overflowed: keep weights
  for (double& w : next) w /= sum;
  weights_ = sanitize(next, weights_);
  std::fill(time_spent_.begin(), time_spent_.end(), 0.0);
  return true;
}

}  // namespace multiray::balance
