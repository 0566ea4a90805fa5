// `uniform`: every alive device gets 1/N of every view (Leria et al., Alg. 1–2, the
// baseline their dynamic balancer is measured against).
//
// | parameter | default | meaning                                   |
// |-----------|---------|-------------------------------------------|
// | layout    | rows    | rows, columns or strips (shuffled strips) |
#pragma once

#include "balance/balancer_base.h"
#include "balance/layout.h"

namespace multiray::balance {

class UniformBalancer final : public BalancerBase {
 public:
  UniformBalancer(int device_count, Layout layout = Layout::Rows);

  std::string name() const override { return "uniform"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override { drop_reported_dead(stats); }
  CutAxis cut_axis() const override { return cut_axis_of(layout_); }

 private:
  Layout layout_;
};

}  // namespace multiray::balance
