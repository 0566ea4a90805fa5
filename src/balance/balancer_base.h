// Bookkeeping shared by the balancers of this library: which devices are alive, and the
// sanitising of measured values that keeps NaN out of every ratio. Another renderer can
// derive from Balancer directly; this class is a convenience, not part of the contract.
#pragma once

#include <vector>

#include "balance/balancer.h"

namespace multiray::balance {

// True for a measurement that can be used (a time, a cost, a sum of work): finite and > 0.
bool usable(double x);

// True for a usable measured time: finite and > 0 ms.
bool valid_time(double ms);

// The work a device did in a frame, in the unit the balancers share out: its samples if
// reported (finite, > 0), else its pixels, else the area of its reported items; 0 if
// none is usable.
double work_done(const DeviceFrameStats& device);

class BalancerBase : public Balancer {
 public:
  // Throws std::invalid_argument unless 1 <= device_count <= 4096.
  explicit BalancerBase(int device_count);

  void drop_device(int index) override;

 protected:
  int device_count() const { return int(alive_.size()); }
  bool alive(int i) const { return i >= 0 && i < device_count() && alive_[size_t(i)]; }
  int alive_count() const;

  // 1/alive_count() for alive devices, 0 for dropped ones (all 0 if none is alive).
  std::vector<double> even() const;
  // `ratios` with dropped devices and invalid entries set to 0, normalised to sum 1. If
  // nothing positive is left, `fallback` treated the same way; then even().
  std::vector<double> sanitize(const std::vector<double>& ratios,
                               const std::vector<double>& fallback) const;
  // Drops the devices `stats` reports dead. Call first thing in update().
  void drop_reported_dead(const FrameStats& stats);
  // The stats of device `i`, or nullptr when the report has no entry for it or the device
  // is dropped.
  const DeviceFrameStats* device_stats(const FrameStats& stats, int i) const;
  // A plan with no work for anyone (shape with no pixels, or every device dropped).
  Plan empty_plan() const;

  // Called once when device `index` is dropped, after it is marked dead.
  virtual void on_drop(int /*index*/) {}

 private:
  std::vector<bool> alive_;
};

}  // namespace multiray::balance
