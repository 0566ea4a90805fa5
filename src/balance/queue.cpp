#include "balance/queue.h"

#include "partition/tiles.h"

namespace multiray::balance {

QueueBalancer::QueueBalancer(int device_count, int tile, int batch, bool deep)
    : BalancerBase(device_count), tile_(tile), batch_(batch), deep_(deep) {}

std::string QueueBalancer::spec() const {
  return "queue:tile=" + std::to_string(tile_) + ":batch=" + std::to_string(batch_) +
         (deep_ ? ":pipeline=deep" : "");  // the paper's form is the default
}

Plan QueueBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  plan.batch = batch_;
  plan.pull_on_ready = !deep_;
  plan.ratios = sanitize(measured_, even());
  const std::vector<Rect> tiles = make_tiles(shape.width, shape.height, tile_);
  for (int view = 0; view < shape.views; ++view)
    for (const Rect& t : tiles) plan.shared.push_back(WorkItem{t, view});
  return plan;
}

void QueueBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  std::vector<double> work(size_t(device_count()), 0.0);
  for (int i = 0; i < device_count(); ++i)
    if (const DeviceFrameStats* d = device_stats(stats, i)) work[size_t(i)] = work_done(*d);
  measured_ = sanitize(work, measured_);
}

}  // namespace multiray::balance
