// `bruder`: prediction-based device shares and a k-d tree of tiles, after V. Bruder,
// S. Frey & T. Ertl, "Prediction-based load balancing and resolution tuning for
// interactive volume raycasting", Visual Informatics 1(2), 2017, §6.2.
//
// Shares. Device i has a cost per unit of work σ_i (ms per unit of pixel weight) for the
// coming frame: FrameShape::device_cost[i] when the renderer predicts it, else σ_i
// measured on the last usable frame (time / pixel weight of the items it rendered; the
// first frame is uniform). The share is r̂_i = (1/σ_i) / Σ_k (1/σ_k), blended with
// uniform as Eq. 3 prints it: r_i = ζ·r̂_i + (1 − ζ)/n over the n alive devices (see
// prediction_shares). With `sigma=A/B/...` the costs are fixed for the whole run: the
// paper's §7.5 static baseline (σ̄_i averaged over all sequences, on the same k-d tiles).
//
// Layout. Every view is cut into `tile`×`tile` tiles (the last row and column may be
// partial); the views' grids are laid side by side, view 0 on the left, into one grid, so
// that one k-d tree distributes all views. A tile costs the pixel weight it holds (its
// area when the frame is unweighted). kd_split_tiles gives each device one rectangle of
// tiles; each tile in it becomes one WorkItem, row by row. With `steal`, devices that run
// dry take the last unstarted tiles of the others (Plan::steal); the paper does not steal.
//
// | parameter | default | meaning                                                   |
// |-----------|---------|-----------------------------------------------------------|
// | zeta      | 0.5     | ζ in [0, 1], weight of the predicted shares (Eq. 3)       |
// | tile      | 8       | tile side in pixels, 1–4096 (paper: 8×8)                  |
// | steal     | 0       | 1: Plan::steal (multiray's addition), 0: as the paper     |
// | sigma     | (none)  | A/B/...: fixed σ̄ per device, > 0 (the §7.5 static)       |
#pragma once

#include "balance/balancer_base.h"
#include "partition/weight_map.h"

namespace multiray::balance {

// Device shares from costs per unit of work `sigma` (ms per unit; entries that are not
// finite and > 0 are unknown) and damping `zeta` in [0, 1], over the devices `alive` marks
// (all of them when `alive` is empty); dropped devices get 0. Known devices weigh 1/σ_i,
// unknown ones the mean weight of the known ones (all equal when none is known); then
// r_i = ζ·r̂_i + (1 − ζ)/n. The result sums to 1 (all 0 when no device is alive).
//
// Two departures from Eq. 3 as printed, r_i = ζ·∏_{j≠i}σ_j / Σ_k σ_k + (1 − ζ)/n:
//  - the prediction term ∏_{j≠i}σ_j / Σ_k σ_k is (1/σ_i)/Σ_k(1/σ_k) only for two devices
//    and does not sum to 1 for more, so the normalised 1/σ form r̂_i is used;
//  - ζ stays where the paper prints it, on the prediction term: ζ = 1 is the pure
//    prediction, ζ = 0 uniform. Reading ζ as a damping toward uniform (ζ on the uniform
//    term, as multiray did before issue 29) gives the same shares only at ζ = 0.5; at
//    ζ = 0.8 a 1 : 3 cost pair gets 0.70/0.30 here and 0.55/0.45 in that reading.
std::vector<double> prediction_shares(const std::vector<double>& sigma, double zeta,
                                      const std::vector<bool>& alive = {});

class BruderBalancer final : public BalancerBase {
 public:
  struct Options {
    // ζ < 1 holds a fast:slow pair away from its ideal split (ζ = 0.5 gives a 3:1 pair
    // 0.625/0.375 instead of 0.75/0.25). The paper's default is kept for the paper's method,
    // and its cost is measured (docs/balancers.md).
    double zeta = 0.5;
    int tile = 8;        // pixels, >= 1
    bool steal = false;  // Plan::steal; the paper's plans are static
    // Work items a device's rectangle is cut into: "rect" (one per view it spans: one
    // launch per device and frame, as the paper renders), "rows" (one per tile row: few
    // launches, and small enough pieces to steal) or "tiles" (one per tile). Every item
    // costs a real device a launch (~0.1 ms on PoCL): with tiles, 768 items a frame at
    // 256x192 made bruder 30% slower than hybrid on CPU + OpenCL.
    std::string items = "rows";
    // Empty: σ_i predicted or measured every frame. Else one fixed σ̄_i > 0 per device
    // (ms per unit of pixel weight; only their ratios matter), the paper's §7.5 static
    // baseline: the costs averaged over all sequences, split on the same k-d tiles.
    std::vector<double> fixed_cost;
  };

  explicit BruderBalancer(int device_count, Options options);

  std::string name() const override { return "bruder"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

  // σ_i measured on the last usable frame (ms per unit of pixel weight), NaN while unknown.
  const std::vector<double>& measured_cost() const { return measured_; }
  // The shares of the last plan.
  const std::vector<double>& shares() const { return shares_; }

 private:
  // σ per device for `shape`: its prediction where usable, else the measured one.
  std::vector<double> costs_for(const FrameShape& shape) const;
  // Pixel weight of device `i`'s rendered work in the last planned frame.
  double work_of(const DeviceFrameStats& d, int i) const;

  Options options_;
  std::vector<double> measured_;  // per device, NaN = unknown
  std::vector<double> shares_;
  // What update() needs of the last plan: its size and weights, each device's planned
  // work (used when a device reports no items).
  bool planned_ = false;
  FrameShape last_size_;  // width, height, views only
  WeightMap last_weights_;
  std::vector<double> planned_work_;
};

}  // namespace multiray::balance
