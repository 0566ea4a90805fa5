// `uniform`: every alive device gets 1/N of every view (Leria et al., Alg. 1–2, the
// baseline their dynamic balancer is measured against).
//
// | parameter | default | meaning                                   |
// |-----------|---------|-------------------------------------------|
// | layout    | rows    | rows, columns or strips (shuffled strips) |
// | bits, strip, items | as dlb's | with layout=strips: the strips, as dlb cuts them |
//
// `uniform:layout=strips` is the baseline Leria et al. measure dlb against (their
// Algorithm 1: equal ratios over the same shuffled strips), so it cuts exactly dlb's strips.
#pragma once

#include "balance/balancer_base.h"
#include "balance/layout.h"

namespace multiray::balance {

class UniformBalancer final : public BalancerBase {
 public:
  UniformBalancer(int device_count, Layout layout = Layout::Rows, StripRule strips = {});

  std::string name() const override { return "uniform"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override { drop_reported_dead(stats); }
  CutAxis cut_axis() const override { return cut_axis_of(layout_); }

 private:
  Layout layout_;
  StripRule strips_;
};

}  // namespace multiray::balance
