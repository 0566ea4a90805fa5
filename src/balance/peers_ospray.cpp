#include "balance/peers_ospray.h"

#include <cstddef>

#include "partition/tiles.h"
#include "partition/weight_map.h"

namespace multiray::balance {

std::vector<OwnedTile> round_robin_tiles(const FrameShape& shape, int tile,
                                         const std::vector<bool>& alive) {
  std::vector<int> ranks;  // alive devices: OSPRay's worker ranks
  for (size_t i = 0; i < alive.size(); ++i)
    if (alive[i]) ranks.push_back(int(i));
  std::vector<OwnedTile> out;
  if (ranks.empty() || shape.pixels() == 0) return out;
  const std::vector<Rect> tiles = make_tiles(shape.width, shape.height, tile);
  out.reserve(tiles.size() * size_t(shape.views));
  size_t t = 0;  // tile number over the whole frame
  for (int view = 0; view < shape.views; ++view)
    for (const Rect& r : tiles)
      out.push_back(OwnedTile{WorkItem{r, view}, ranks[t++ % ranks.size()]});
  return out;
}

std::vector<bool> OsprayStaticBalancer::alive_mask() const {
  std::vector<bool> mask(static_cast<size_t>(device_count()));
  for (int i = 0; i < device_count(); ++i) mask[size_t(i)] = alive(i);
  return mask;
}

std::vector<bool> OsprayDynamicBalancer::alive_mask() const {
  std::vector<bool> mask(static_cast<size_t>(device_count()));
  for (int i = 0; i < device_count(); ++i) mask[size_t(i)] = alive(i);
  return mask;
}

OsprayStaticBalancer::OsprayStaticBalancer(int device_count, int tile)
    : BalancerBase(device_count), tile_(tile) {}

std::string OsprayStaticBalancer::spec() const {
  return "ospray-static:tile=" + std::to_string(tile_);
}

Plan OsprayStaticBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  for (const OwnedTile& t : round_robin_tiles(shape, tile_, alive_mask()))
    plan.assigned[size_t(t.owner)].push_back(t.item);
  // The share of the frame's samples each worker owns.
  std::vector<double> share(size_t(device_count()), 0.0);
  if (shape.pixels() > 0) {
    const WeightMap weights(shape.width, shape.height, shape.views, shape.pixel_weight);
    for (size_t i = 0; i < share.size(); ++i) share[i] = weights.sum(plan.assigned[i]);
  }
  plan.ratios = sanitize(share, even());
  return plan;
}

OsprayDynamicBalancer::OsprayDynamicBalancer(int device_count, int tile, int prefetch)
    : BalancerBase(device_count), tile_(tile), prefetch_(prefetch) {}

std::string OsprayDynamicBalancer::spec() const {
  return "ospray-dynamic:tile=" + std::to_string(tile_) + ":prefetch=" + std::to_string(prefetch_);
}

Plan OsprayDynamicBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  plan.batch = prefetch_;
  plan.ratios = sanitize(measured_, even());
  // The master pre-allocates `prefetch` of each worker's own tiles; the rest it keeps.
  for (const OwnedTile& t : round_robin_tiles(shape, tile_, alive_mask())) {
    std::vector<WorkItem>& own = plan.assigned[size_t(t.owner)];
    if (int(own.size()) < prefetch_)
      own.push_back(t.item);
    else
      plan.shared.push_back(t.item);
  }
  return plan;
}

void OsprayDynamicBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  std::vector<double> work(size_t(device_count()), 0.0);
  for (int i = 0; i < device_count(); ++i)
    if (const DeviceFrameStats* d = device_stats(stats, i)) work[size_t(i)] = work_done(*d);
  measured_ = sanitize(work, measured_);
}

}  // namespace multiray::balance
