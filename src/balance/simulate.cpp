#include "balance/simulate.h"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <queue>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

#include "balance/dispatcher.h"
#include "partition/weight_map.h"

namespace multiray::balance {

namespace {
// U(−1, 1) from 53 random bits: the same on every standard library.
double symmetric_unit(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1p-52 - 1.0; }

// Time to process `cost` starting at `start` on a device whose speed changes at
// `change_at`.
double run_time(double start, double cost, double speed, double change_at, double speed_after) {
  if (start >= change_at) return cost / speed_after;
  const double before = (change_at - start) * speed;  // cost doable before the change
  if (cost <= before) return cost / speed;
  return (change_at - start) + (cost - before) / speed_after;
}

}  // namespace

CostFn uniform_cost(const FrameShape& shape, double ms_per_sample) {
  auto map =
      std::make_shared<WeightMap>(shape.width, shape.height, shape.views, shape.pixel_weight);
  return [map, ms_per_sample](const WorkItem& item) { return map->sum(item) * ms_per_sample; };
}

CostFn pixel_cost(const FrameShape& shape,
                  const std::function<double(int view, int x, int y)>& ms_per_sample) {
  validate_shape(shape);
  std::vector<float> cost(size_t(shape.pixels()));
  size_t p = 0;
  for (int v = 0; v < shape.views; ++v)
    for (int y = 0; y < shape.height; ++y)
      for (int x = 0; x < shape.width; ++x, ++p)
        cost[p] =
            float(ms_per_sample(v, x, y) * (shape.weighted() ? shape.pixel_weight[p] : 1.0f));
  auto map = std::make_shared<WeightMap>(shape.width, shape.height, shape.views, cost);
  return [map](const WorkItem& item) { return map->sum(item); };
}

FrameStats simulate(const Plan& plan, const FrameShape& shape,
                    const std::vector<SimDevice>& devices, const CostFn& cost, int frame,
                    uint64_t seed) {
  const size_t n = devices.size();
  if (plan.assigned.size() != n)
    throw std::invalid_argument("plan has " + std::to_string(plan.assigned.size()) +
                                " device lists for " + std::to_string(n) + " devices");
  Dispatcher dispatch(plan, shape);

  FrameStats stats;
  stats.frame = frame;
  stats.shape = shape;
  stats.devices.resize(n);
  std::vector<double> frame_factor(n, 1.0);
  std::mt19937_64 rng(seed * 0x9e3779b97f4a7c15ull + uint64_t(frame));
  // Devices by (clock, index): the device that is free first acts next, the lowest index
  // on ties — the order in which real devices would ask the dispatcher.
  using Event = std::pair<double, size_t>;
  std::priority_queue<Event, std::vector<Event>, std::greater<Event>> ready;
  for (size_t i = 0; i < n; ++i) {
    const SimDevice& d = devices[i];
    if (d.alive && !(d.speed > 0 && d.speed_after > 0))
      throw std::invalid_argument("device " + std::to_string(i) + " has a speed <= 0");
    frame_factor[i] = 1 + d.frame_noise * symmetric_unit(rng);
    stats.devices[i].alive = d.alive;
    if (d.alive) ready.push({0.0, i});
  }

  while (!ready.empty()) {
    const auto [clock, i] = ready.top();
    ready.pop();
    uint32_t id;
    if (!dispatch.next(int(i), id)) continue;  // out of work: the device is done
    const WorkItem& item = dispatch.items()[id];
    const double w = dispatch.weight(id);
    const SimDevice& d = devices[i];
    const double c = std::max(0.0, cost(item)) * (1 + d.item_noise * symmetric_unit(rng));
    const double start = clock + d.item_overhead_ms;
    const double dt =
        d.item_overhead_ms + run_time(start, c, d.speed * frame_factor[i], d.change_at_ms,
                                      d.speed_after * frame_factor[i]);
    DeviceFrameStats& out = stats.devices[i];
    out.items.push_back(ItemReport{item, dt, w, dt, id});
    out.time_ms = out.busy_ms = clock + dt;
    out.samples += w;
    out.pixels += double(item.rect.area());
    ready.push({clock + dt, i});
  }
  return stats;
}

std::vector<SimFrame> simulate_run(
    Balancer& balancer, const FrameShape& shape,
    const std::function<std::vector<SimDevice>(int frame)>& devices_at, const CostFn& cost,
    int frames, uint64_t seed) {
  std::vector<SimFrame> run;
  for (int f = 0; f < frames; ++f) {
    SimFrame sf;
    sf.plan = balancer.plan(shape, f);
    sf.stats = simulate(sf.plan, shape, devices_at(f), cost, f, seed);
    balancer.update(sf.stats);
    run.push_back(std::move(sf));
  }
  return run;
}

}  // namespace multiray::balance
