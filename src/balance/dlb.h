// `dlb`: the workload-ratio dynamic load balancer of Leria, Mäkitalo, Ikkala &
// Jääskeläinen, "Dynamic load balancing for real-time multiview path tracing on multi-GPU
// architectures", Virtual Reality & Intelligent Hardware 7(4), 393-405, 2025.
//
// Every view is cut into shuffled strips (van Antwerpen et al.) and device i renders the
// fraction w_i of every view's strips, all views in the same frame. Device i's rate is
// r_i = tasks_i / Δ_i (tasks: pixels it rendered, Δ_i: its time) and the ratios are
// w_i = r_i / Σr. Ratios are only revisited every `interval` frames, and only when the
// devices are imbalanced: some device's mean time over the window lies outside ±`band`
// of the first device's. While imbalanced, a device slower than the global mean has its
// time recorded as `slow`·(its local mean over the window) + (1 − `slow`)·(its latest
// time).
//
// `slow` departs from the paper, which says how the constant enters Δ: a slow device's
// time is recorded as 0.75 of its local mean, Δ = 0.75·mean. Taken so, the update has a
// biased fixed point (the slow device keeps 1/0.75 of its fair share and a 3:1 pair stays
// ~33% apart for ever), so we use 0.75 as the weight of the slow device's history instead,
// Δ = 0.75·mean + 0.25·latest: a single slow frame cannot make it shed work, and with
// steady timings the update is exact (w_i ∝ speed in one step). docs/balancers.md.
//
// | parameter | default | meaning                                             |
// |-----------|---------|-----------------------------------------------------|
// | interval  | 5       | frames between imbalance checks (1–1000)            |
// | band      | 0.1     | tolerated relative time difference to device 0      |
// | slow      | 0.75    | weight of a slow device's local mean, [0, 1]        |
// | bits      | auto    | log2 strips per view; auto: from `strip`            |
// | strip     | 32      | least pixels per strip when bits=auto (1–65536)     |
// | items     | 16384   | most strips per frame, all views, when bits=auto    |
// | layout    | strips  | strips as in the paper, or views: whole views per    |
// |           |         | device (multiray's own mapping, not the paper's)    |
//
// The strip count: Leria et al. choose b to maximise the strips 2^b per view (2^19 at
// 1280x720, ~1.8 px a strip; `strip=1`), which suits a GPU that runs a work-item per
// pixel whatever the strip. Our CPU devices render an item at a time, and tiny strips
// cost there: on two one-thread CPU devices at 320x180, 4 spp, the devices' busy time per
// frame was ~66 ms with strips of 225 or 56 px, ~80 ms with 14 px, ~106 ms with 3.5 px
// and ~130 ms with the paper's 1.8 px (docs/balancers.md). So the default follows the
// paper's rule, the most strips, down to 32 px per strip; `strip=128` is multiray's
// earlier 128–256 px. And since the count is per view, many views multiply it: 81 views
// of 1,024 strips were 82,944 items a frame, whose cost made dlb slower than uniform on a
// 9x9 grid (docs/benchmarks.md). So `items` caps the strips of a frame (all views): 2^b
// per view with 2^b · views <= items, which leaves one view at 1280x720 (2^14) and a 3x3
// grid at 320x180 (9 x 2^10) as they were and gives 9x9 at 320x180 2^7 strips a view.
#pragma once

#include "balance/balancer_base.h"
#include "balance/layout.h"

namespace multiray::balance {

class DlbBalancer final : public BalancerBase {
 public:
  // `strips`: how many strips a view is cut into (layout.h).
  // `layout` Strips (shuffled strips of every view, as in the paper) or Views (whole views
  // per device: multiray's own mapping, see layout.h).
  DlbBalancer(int device_count, int interval = 5, double band = 0.1, double slow = 0.75,
              StripRule strips = {}, Layout layout = Layout::Strips);

  std::string name() const override { return "dlb"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  CutAxis cut_axis() const override { return cut_axis_of(layout_); }

  const std::vector<double>& ratios() const { return ratios_; }
  // Number of times the ratios were recomputed (imbalance found at a check).
  int rebalances() const { return rebalances_; }

 private:
  void on_drop(int index) override;
  void check();

  Layout layout_;
  int interval_;
  double band_, slow_;
  StripRule strips_;
  std::vector<double> ratios_;
  // The current window: per device, sums of time and tasks over frames with a usable
  // measurement, how many there were, and the latest time.
  std::vector<double> time_sum_, task_sum_, last_time_;
  std::vector<int> count_;
  int frames_in_window_ = 0;
  int rebalances_ = 0;
};

}  // namespace multiray::balance
