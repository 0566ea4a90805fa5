// `cycles`: Blender Cycles' multi-device balancing, rewritten from its published sources
// (intern/cycles/integrator/work_balancer.cpp, render_scheduler.cpp and path_trace.cpp,
// Blender 3.0 and later) so that multiray can be measured against it. The facts are
// Cycles'; the code is ours.
//
// Weights. Every device starts with the weight 1/N. Each device's measured time is
// accumulated until a rebalance changes the weights (Cycles' WorkBalanceInfo::time_spent).
// A rebalance computes the mean time t̄ of the N alive devices and, for each device,
// a target time moved 1/N of the way from its own time toward the mean,
//   target_i = t_i + (t̄ − t_i)/N,   w_i ← w_i · target_i / t_i,   then Σw = 1.
// Nothing changes (and the accumulated times are kept) unless some device's target is
// more than 2% off the mean, |1 − target_i/t̄| > 0.02: with N devices that is a device
// whose time is more than 2%·N/(N−1) off the mean (4% for two). So a converged pair can
// stay up to 4% imbalanced; that dead band is Cycles', kept on purpose.
//
// When. Rebalancing is on wall time, not per frame (RenderScheduler::work_need_rebalance):
// right after the first frame that measured every device; then after every frame that
// follows a rebalance which changed the weights (so a change is followed up at once);
// otherwise only once more than `interval_ms` passed since the last rebalance was
// considered. Cycles' interval is 1 s (kRebalanceIntervalInSeconds). multiray's clock is
// the sum of the measured frame times (the slowest alive device of each usable frame), so
// simulation stays deterministic.
//
// Layout. Each view is cut into contiguous row slices in device order, device i getting
// max(1, round(height · w_i)) rows and the last alive device the rest, as Cycles'
// foreach_sliced_buffer_params does; dropped devices get none. Area, not pixel_weight,
// is split. Plan::ratios are the weights.
//
// multiray's additions, for the Balancer contract: a frame counts only if every alive
// device reported a usable time (Cycles always has one per device); a rebalance that
// would give a non-finite weight is skipped; a dropped device's weight goes to the others
// in proportion, the accumulated times restart, and the next usable frame rebalances.
//
// | parameter   | default | meaning                                                   |
// |-------------|---------|-----------------------------------------------------------|
// | interval_ms | 1000    | measured time between rebalances once balanced (0–1e9 ms) |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class CyclesBalancer final : public BalancerBase {
 public:
  explicit CyclesBalancer(int device_count, double interval_ms = 1000);

  std::string name() const override { return "cycles"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  CutAxis cut_axis() const override { return CutAxis::rows; }  // row slices

  // The weights the next plan uses (0 for dropped devices).
  const std::vector<double>& weights() const { return weights_; }
  // Rebalances considered (Cycles' num_rebalance_requested) and those that changed the
  // weights (num_rebalance_changes).
  int rebalances_requested() const { return requested_; }
  int rebalances_changed() const { return changed_; }

 private:
  void on_drop(int index) override;
  // Cycles' work_balance_do_rebalance over the accumulated times: true if the weights
  // changed (the accumulated times then restart).
  bool rebalance();

  double interval_ms_;
  std::vector<double> weights_;
  std::vector<double> time_spent_;  // ms per device since the last change of the weights
  double clock_ms_ = 0;             // sum of measured frame times
  double last_rebalance_ms_ = 0;    // clock when a rebalance was last considered
  bool measured_ = false;           // some usable frame was seen since start or a drop
  bool last_changed_ = false;
  int requested_ = 0, changed_ = 0;
};

// Cycles' slicing of one view: per device [y0, y1) rows, max(1, round(height·w_i)) each
// (capped by what is left), the last device with a positive weight taking the rest;
// devices with a weight of 0 get no rows. Exposed for tests.
std::vector<Rect> cycles_slices(int width, int height, const std::vector<double>& weights);

}  // namespace multiray::balance
