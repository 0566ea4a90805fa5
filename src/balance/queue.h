// `queue`: the dynamic tile queue of Seo et al. (distributed mobile ray tracing,
// strategy I, §4.1): the frame is cut into square tiles that all sit in Plan::shared,
// and every device pulls `batch` tiles whenever it is idle, until none are left. No
// statistics are needed; balance is as fine as one batch, paid for by one dispatch per
// batch. Plan::ratios reports last frame's measured work shares (even at first), since
// the queue itself intends none.
//
// Behind a link (a worker rank of a distributed run), `pipeline` says how tiles travel.
// `paper`, the paper's form: a worker holds one tile index at a time and is sent the next
// when it reports the last one rendered; only the upload of that tile's pixels overlaps
// rendering the next, so every tile still pays one round trip. `deep` is ours: the master
// keeps --depth tiles at the worker (2, or adapting up to 32), which hides the round trip
// (distributed/remote_device.h). Local devices are not affected.
//
// | parameter | default | meaning                                   |
// |-----------|---------|-------------------------------------------|
// | tile      | 64      | tile edge in pixels (1–4096)              |
// | batch     | 1       | tiles per pull (1–1024)                   |
// | pipeline  | paper   | paper or deep (ours): tiles to a worker   |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class QueueBalancer final : public BalancerBase {
 public:
  // `deep`: tiles to a worker rank kept --depth deep (ours) instead of the paper's one at
  // a time on its ready report.
  QueueBalancer(int device_count, int tile = 64, int batch = 1, bool deep = false);

  std::string name() const override { return "queue"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

 private:
  int tile_, batch_;
  bool deep_;
  std::vector<double> measured_;  // last usable work shares
};

}  // namespace multiray::balance
