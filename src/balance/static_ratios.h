// `static`: fixed work ratios for the whole run, a baseline of ours. (The papers' static
// forms are other balancers: `ospray-static`, and Bruder et al. §7.5's `bruder:sigma=`.)
// Either the user gives them ("static:ratios=3/1"), or they are calibrated once: the
// first frame is split evenly and each device's speed (work / time) in it becomes its
// ratio from then on. Calibration waits for a frame in which every alive device reported
// a usable time and some work; dropped devices' shares go to the others in proportion.
//
// | parameter | default   | meaning                                          |
// |-----------|-----------|--------------------------------------------------|
// | ratios    | calibrate | '/'-separated non-negative weights, one a device |
// | layout    | rows      | rows, columns or strips                          |
// | bits, strip, items | as dlb's | with layout=strips: the strips (layout.h) |
#pragma once

#include "balance/balancer_base.h"
#include "balance/layout.h"

namespace multiray::balance {

class StaticBalancer final : public BalancerBase {
 public:
  // Empty `ratios`: calibrate from the first usable frame.
  StaticBalancer(int device_count, std::vector<double> ratios, Layout layout = Layout::Rows,
                 StripRule strips = {});

  std::string name() const override { return "static"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  CutAxis cut_axis() const override { return cut_axis_of(layout_); }

  bool calibrated() const { return !ratios_.empty(); }

 private:
  std::vector<double> ratios_;  // empty until calibrated
  bool given_;                  // ratios came from the spec
  Layout layout_;
  StripRule strips_;
};

}  // namespace multiray::balance
