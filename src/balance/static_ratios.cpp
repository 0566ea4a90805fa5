#include "balance/static_ratios.h"

#include <cstddef>
#include <sstream>

namespace multiray::balance {

StaticBalancer::StaticBalancer(int device_count, std::vector<double> ratios, Layout layout,
                               StripRule strips)
    : BalancerBase(device_count),
      ratios_(std::move(ratios)),
      given_(!ratios_.empty()),
      layout_(layout),
      strips_(strips) {}

std::string StaticBalancer::spec() const {
  std::ostringstream s;
  s << "static";
  if (given_) {
    s << ":ratios=";
    for (size_t i = 0; i < ratios_.size(); ++i) s << (i ? "/" : "") << ratios_[i];
  }
  s << ":layout=" << to_string(layout_);
  if (layout_ == Layout::Strips) s << ":" << to_spec(strips_);
  return s.str();
}

Plan StaticBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  return plan_from_ratios(shape, calibrated() ? sanitize(ratios_, even()) : even(), layout_,
                          strips_);
}

void StaticBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  if (calibrated()) return;
  std::vector<double> speed(size_t(device_count()), 0.0);
  for (int i = 0; i < device_count(); ++i) {
    if (!alive(i)) continue;
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms) || !(work_done(*d) > 0)) return;  // try next frame
    speed[size_t(i)] = work_done(*d) / d->time_ms;
  }
  ratios_ = sanitize(speed, even());
}

}  // namespace multiray::balance
