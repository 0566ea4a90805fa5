#include "balance/balancer_base.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace multiray::balance {

namespace {
constexpr int kMaxDevices = 4096;
}  // namespace

bool usable(double x) { return std::isfinite(x) && x > 0; }

bool valid_time(double ms) { return usable(ms); }

double work_done(const DeviceFrameStats& device) {
  if (usable(device.samples)) return device.samples;
  if (usable(device.pixels)) return device.pixels;
  double area = 0;
  for (const ItemReport& r : device.items) area += double(r.item.rect.area());
  return area;
}

BalancerBase::BalancerBase(int device_count) {
  if (device_count < 1 || device_count > kMaxDevices)
    throw std::invalid_argument("device count " + std::to_string(device_count) +
                                " is outside 1.." + std::to_string(kMaxDevices));
  alive_.assign(size_t(device_count), true);
}

void BalancerBase::drop_device(int index) {
  if (!alive(index)) return;
  alive_[size_t(index)] = false;
  on_drop(index);
}

int BalancerBase::alive_count() const {
  int n = 0;
  for (bool a : alive_) n += a ? 1 : 0;
  return n;
}

std::vector<double> BalancerBase::even() const {
  std::vector<double> r(alive_.size(), 0.0);
  const int n = alive_count();
  for (size_t i = 0; i < r.size(); ++i)
    if (alive_[i]) r[i] = 1.0 / n;
  return r;
}

std::vector<double> BalancerBase::sanitize(const std::vector<double>& ratios,
                                           const std::vector<double>& fallback) const {
  for (const std::vector<double>* source : {&ratios, &fallback}) {
    std::vector<double> r(alive_.size(), 0.0);
    double sum = 0;
    for (size_t i = 0; i < r.size() && i < source->size(); ++i)
      if (alive_[i] && usable((*source)[i])) sum += r[i] = (*source)[i];
    if (usable(sum)) {
      for (double& x : r) x /= sum;
      return r;
    }
  }
  return even();
}

void BalancerBase::drop_reported_dead(const FrameStats& stats) {
  for (size_t i = 0; i < stats.devices.size() && i < alive_.size(); ++i)
    if (!stats.devices[i].alive) drop_device(int(i));
}

const DeviceFrameStats* BalancerBase::device_stats(const FrameStats& stats, int i) const {
  if (!alive(i) || size_t(i) >= stats.devices.size()) return nullptr;
  return &stats.devices[size_t(i)];
}

Plan BalancerBase::empty_plan() const {
  Plan plan;
  plan.assigned.resize(alive_.size());
  plan.ratios = alive_count() > 0 ? even() : std::vector<double>(alive_.size(), 0.0);
  return plan;
}

}  // namespace multiray::balance
