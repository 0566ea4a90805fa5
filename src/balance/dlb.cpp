#include "balance/dlb.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "balance/layout.h"
#include "partition/shuffled_strips.h"

namespace multiray::balance {

DlbBalancer::DlbBalancer(int device_count, int interval, double band, double slow,
                         StripRule strips, Layout layout)
    : BalancerBase(device_count),
      layout_(layout),
      interval_(interval),
      band_(band),
      slow_(slow),
      strips_(strips),
      ratios_(even()),
      time_sum_(size_t(device_count), 0.0),
      task_sum_(size_t(device_count), 0.0),
      last_time_(size_t(device_count), 0.0),
      count_(size_t(device_count), 0) {}

std::string DlbBalancer::spec() const {
  std::ostringstream s;
  s << "dlb:interval=" << interval_ << ":band=" << band_ << ":slow=" << slow_ << ":"
    << to_spec(strips_) << ":layout=" << to_string(layout_);
  return s.str();
}

void DlbBalancer::on_drop(int /*index*/) { ratios_ = sanitize(ratios_, even()); }

Plan DlbBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  return plan_from_ratios(shape, ratios_, layout_, strips_);
}

void DlbBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms) || !(work_done(*d) > 0)) continue;
    time_sum_[size_t(i)] += d->time_ms;
    task_sum_[size_t(i)] += work_done(*d);
    last_time_[size_t(i)] = d->time_ms;
    ++count_[size_t(i)];
  }
  if (++frames_in_window_ < interval_) return;
  check();
  frames_in_window_ = 0;
  std::fill(time_sum_.begin(), time_sum_.end(), 0.0);
  std::fill(task_sum_.begin(), task_sum_.end(), 0.0);
  std::fill(count_.begin(), count_.end(), 0);
}

void DlbBalancer::check() {
  const size_t n = size_t(device_count());
  std::vector<double> mean_time(n, 0.0);
  double reference = 0, global = 0;
  int measured = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!alive(int(i)) || count_[i] == 0) continue;
    mean_time[i] = time_sum_[i] / count_[i];
    if (measured == 0) reference = mean_time[i];  // the first device's time
    global += mean_time[i];
    ++measured;
  }
  if (measured == 0 || !(reference > 0)) return;
  global /= measured;
  bool imbalanced = false;
  for (size_t i = 0; i < n; ++i)
    if (mean_time[i] > 0 && std::abs(mean_time[i] - reference) > band_ * reference)
      imbalanced = true;
  if (!imbalanced) return;

  // r_i = tasks_i / Δ_i over the measured devices; the others keep their share.
  std::vector<double> rate(n, 0.0);
  double mass = 0, rate_sum = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(mean_time[i] > 0)) continue;
    double delta = mean_time[i];
    if (delta > global) delta = slow_ * mean_time[i] + (1 - slow_) * last_time_[i];
    rate[i] = (task_sum_[i] / count_[i]) / delta;
    rate_sum += rate[i];
    mass += ratios_[i];
  }
  if (!(rate_sum > 0) || !std::isfinite(rate_sum) || !(mass > 0)) return;
  std::vector<double> next = ratios_;
  for (size_t i = 0; i < n; ++i)
    if (rate[i] > 0) next[i] = mass * rate[i] / rate_sum;
  ratios_ = sanitize(next, ratios_);
  ++rebalances_;
}

}  // namespace multiray::balance
