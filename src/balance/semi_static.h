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
// The shares are turned into one contiguous range of lines per device by binary search
// in a piecewise-linear CDF of sample counts. The paper's form is the default: the CDF is
// built from the samples the devices reported for the previous frame (per column: each
// reported item's samples spread over its area, so the CDF is piecewise linear over the
// devices' last regions) and the image is split vertically "for all test cases" (views
// side by side; the cut falls at pixel precision inside a column). Ours is an
// option: `cdf=frame` builds the CDF from this frame's own pixel_weight when there is one
// (irregular sampling: the split then follows the samples of the frame being rendered,
// not those of the last one), and `split=rows` cuts scanline ranges at pixel precision
// (views end to end); `semi-static:split=rows:cdf=frame` is multiray's form.
//
// | parameter | default  | meaning                                                   |
// |-----------|----------|-----------------------------------------------------------|
// | alpha     | 0.4      | blend towards the ideal split, (0, 1]                     |
// | split     | columns  | columns (Harada: vertical bands) or rows (scanline ranges)|
// | cdf       | reported | reported (last frame's reports) or frame (this frame's map)|
// | cut       | pixel    | pixel, or line: cuts rounded to whole lines (each at most  |
// |           |          | half a line off), as the top of Harada's hierarchy uses    |
#pragma once

#include "balance/balancer_base.h"
#include "balance/line_density.h"

namespace multiray::balance {

struct SemiStaticOptions {
  double alpha = 0.4;
  LineAxis split = LineAxis::columns;
  bool cdf_from_frame = false;  // cdf=frame: this frame's pixel_weight when it has one
  // cut=line: whole lines, so that a device (an MPI rank) gets one band, not a band and
  // the partial lines at its ends, each of which a rank would plan and learn from alone.
  bool whole_lines = false;
};

class SemiStaticBalancer final : public BalancerBase {
 public:
  SemiStaticBalancer(int device_count, SemiStaticOptions options = {});

  std::string name() const override { return "semi-static"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  CutAxis cut_axis() const override {
    return options_.split == LineAxis::rows ? CutAxis::rows : CutAxis::columns;
  }

  // Current shares of the samples, sum 1 over alive devices.
  const std::vector<double>& shares() const { return shares_; }

 private:
  void on_drop(int index) override;
  // Weight of every flat line of `shape` for the split: samples, or their estimate.
  std::vector<double> line_weights(const FrameShape& shape) const;
  void learn_density(const FrameStats& stats);

  SemiStaticOptions options_;
  std::vector<double> shares_;
  // Samples per pixel of each flat line in the last report, and the size it applies to.
  std::vector<double> density_;
  FrameShape density_shape_;
};

}  // namespace multiray::balance
