// `queue`: the dynamic tile queue of Seo et al. (distributed mobile ray tracing,
// strategy I, §4.1): the frame is cut into square tiles that all sit in Plan::shared,
// and every device pulls `batch` tiles whenever it is idle, until none are left. No
// statistics are needed; balance is as fine as one batch, paid for by one dispatch per
// batch. Plan::ratios reports last frame's measured work shares (even at first), since
// the queue itself intends none.
//
// | parameter | default | meaning                       |
// |-----------|---------|-------------------------------|
// | tile      | 64      | tile edge in pixels (1–4096)  |
// | batch     | 1       | tiles per pull (1–1024)       |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class QueueBalancer final : public BalancerBase {
 public:
  QueueBalancer(int device_count, int tile = 64, int batch = 1);

  std::string name() const override { return "queue"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

 private:
  int tile_, batch_;
  std::vector<double> measured_;  // last usable work shares
};

}  // namespace multiray::balance
