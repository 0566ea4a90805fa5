#include "balance/simulate.h"

#include <algorithm>
#include <cstddef>
#include <deque>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

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

struct DeviceState {
  std::deque<WorkItem> pending;  // not started, own + pulled
  double remaining = 0;          // their weight (pixels × weight)
  double clock = 0;
  bool active = false;
};
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
  const WeightMap weight(shape.width, shape.height, shape.views, shape.pixel_weight);

  FrameStats stats;
  stats.frame = frame;
  stats.shape = shape;
  stats.devices.resize(n);
  std::vector<DeviceState> state(n);
  std::vector<double> frame_factor(n, 1.0);
  std::mt19937_64 rng(seed * 0x9e3779b97f4a7c15ull + uint64_t(frame));
  for (size_t i = 0; i < n; ++i) {
    const SimDevice& d = devices[i];
    if (d.alive && !(d.speed > 0 && d.speed_after > 0))
      throw std::invalid_argument("device " + std::to_string(i) + " has a speed <= 0");
    frame_factor[i] = 1 + d.frame_noise * symmetric_unit(rng);
    state[i].pending.assign(plan.assigned[i].begin(), plan.assigned[i].end());
    state[i].remaining = weight.sum(plan.assigned[i]);
    state[i].active = d.alive;
    stats.devices[i].alive = d.alive;
  }
  std::deque<WorkItem> shared(plan.shared.begin(), plan.shared.end());
  const size_t batch = size_t(std::max(plan.batch, 1));

  for (;;) {
    // The device that is free first (lowest index on ties) acts next.
    size_t i = n;
    for (size_t j = 0; j < n; ++j)
      if (state[j].active && (i == n || state[j].clock < state[i].clock)) i = j;
    if (i == n) break;
    DeviceState& me = state[i];

    if (me.pending.empty() && !shared.empty()) {
      for (size_t k = 0; k < batch && !shared.empty(); ++k) {
        me.remaining += weight.sum(shared.front());
        me.pending.push_back(shared.front());
        shared.pop_front();
      }
    }
    WorkItem item;
    if (!me.pending.empty()) {
      item = me.pending.front();
      me.pending.pop_front();
      me.remaining -= weight.sum(item);
    } else if (plan.steal) {
      // The most not-started work, strictly positive (as the engine does); lowest index on
      // ties.
      size_t victim = n;
      double most = 0;
      for (size_t j = 0; j < n; ++j)
        if (j != i && !state[j].pending.empty() && state[j].remaining > most)
          most = state[j].remaining, victim = j;
      if (victim == n) {
        me.active = false;
        continue;
      }
      item = state[victim].pending.back();
      state[victim].pending.pop_back();
      state[victim].remaining -= weight.sum(item);
    } else {
      me.active = false;
      continue;
    }
    const double w = weight.sum(item);
    const SimDevice& d = devices[i];
    const double c = std::max(0.0, cost(item)) * (1 + d.item_noise * symmetric_unit(rng));
    const double start = me.clock + d.item_overhead_ms;
    const double dt =
        d.item_overhead_ms + run_time(start, c, d.speed * frame_factor[i], d.change_at_ms,
                                      d.speed_after * frame_factor[i]);
    me.clock += dt;
    DeviceFrameStats& out = stats.devices[i];
    out.items.push_back(ItemReport{item, dt, w});
    out.time_ms = out.busy_ms = me.clock;
    out.samples += w;
    out.pixels += double(item.rect.area());
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
