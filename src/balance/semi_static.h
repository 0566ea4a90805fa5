// `semi-static`: Harada's split for multi-GPU rendering (GPU Pro 7, ch. 4, "Semi-static
// load balancing"), with irregular sample counts: the chapter's adaptive edge sampling
// (after Mitchell 1987) and foveated sampling (Harada & Fujita 2014).
//
// After each frame, device i's speed is p_i = n_i / t_i (n_i: samples it rendered,
// t_i: its time). Had the frame been split ideally, all devices would have finished at
// T = N / Σp_i, device i rendering n_i* = T·p_i. The new share blends the two:
// n_i ← (1−α)·n_i + α·n_i*, which damps the reaction to noise and to the fact that p_i was
// measured on a region the device will only partly render again.
//
// The shares are turned into one contiguous scanline range per device (views laid end to
// end) by binary search in a piecewise-linear CDF of sample counts: from the frame's own
// pixel_weight when given (irregular sampling: devices then get equal work, not equal
// area), otherwise from the per-row sample densities the devices reported for last frame.
//
// | parameter | default | meaning                                     |
// |-----------|---------|---------------------------------------------|
// | alpha     | 0.4     | blend towards the ideal split, (0, 1]       |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class SemiStaticBalancer final : public BalancerBase {
 public:
  SemiStaticBalancer(int device_count, double alpha = 0.4);

  std::string name() const override { return "semi-static"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

  // Current shares of the samples, sum 1 over alive devices.
  const std::vector<double>& shares() const { return shares_; }

 private:
  void on_drop(int index) override;

  double alpha_;
  std::vector<double> shares_;
  // Samples per pixel of each flat row in the last report, and the size it applies to.
  std::vector<double> density_;
  FrameShape density_shape_;
};

}  // namespace multiray::balance
