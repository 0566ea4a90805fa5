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
  return simulate_linked(plan, shape, devices, cost, SimLink{}, frame, seed).stats;
}

namespace {

// A result message: ready at the device at `ready` ms, `bytes` long.
struct Message {
  double ready = 0, bytes = 0;
  size_t device = 0;
};

// When the master has received every message: each crosses after one latency, one at a
// time on a shared master link (first ready, first sent), or on its device's own link.
double last_arrival(std::vector<Message> messages, size_t devices, const SimLink& link) {
  const double bytes_per_ms = link.mbit_per_s > 0 ? link.mbit_per_s * 1e6 / 8 / 1e3 : 0;
  std::sort(messages.begin(), messages.end(),
            [](const Message& a, const Message& b) { return a.ready < b.ready; });
  std::vector<double> link_free(link.shared_master ? 1 : devices, 0.0);
  double last = 0;
  for (const Message& m : messages) {
    double& free = link_free[link.shared_master ? 0 : m.device];
    const double start = std::max(m.ready + link.latency_ms, free);
    const double done = start + (bytes_per_ms > 0 ? m.bytes / bytes_per_ms : 0.0);
    free = done;
    last = std::max(last, done);
  }
  return last;
}

}  // namespace

SimFrame simulate_linked(const Plan& plan, const FrameShape& shape,
                         const std::vector<SimDevice>& devices, const CostFn& cost,
                         const SimLink& link, int frame, uint64_t seed) {
  const size_t n = devices.size();
  if (plan.assigned.size() != n)
    throw std::invalid_argument("plan has " + std::to_string(plan.assigned.size()) +
                                " device lists for " + std::to_string(n) + " devices");
  Dispatcher dispatch(plan, shape);
  // Static plans (no queue, no stealing) send each device's results once, at its end.
  const bool batched_results = plan.shared.empty() && !plan.steal;

  SimFrame out;
  out.plan = plan;
  FrameStats& stats = out.stats;
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
    if (!(d.frame_overhead_ms >= 0 && d.contention >= 0 && d.launch_ms >= 0))
      throw std::invalid_argument("device " + std::to_string(i) +
                                  " has a negative frame overhead, launch cost or contention");
    stats.devices[i].alive = d.alive;
    stats.devices[i].rested = d.alive && plan.rests(i);
    if (d.alive) out.speed_sum += d.speed * frame_factor[i];  // resting ones too: a bound
    if (d.alive && !plan.rests(i))  // frame start; a resting device is not started
      ready.push({link.latency_ms + d.frame_overhead_ms, i});
  }
  // When each device ran out of work (contention counts the devices still at work).
  std::vector<double> done_at(n, std::numeric_limits<double>::infinity());
  auto at_work = [&](double t) {
    int k = 0;
    for (size_t j = 0; j < n; ++j)
      k += devices[j].alive && !plan.rests(j) && link.latency_ms <= t && done_at[j] > t;
    return std::max(k, 1);
  };

  std::vector<Message> messages;
  std::vector<double> unsent(n, 0.0);  // batched results: pixels not yet sent
  while (!ready.empty()) {
    auto [clock, i] = ready.top();
    ready.pop();
    uint32_t id;
    Dispatcher::Via via;
    if (!dispatch.next(int(i), id, &via)) {  // out of work: the device is done
      done_at[i] = clock;
      if (unsent[i] > 0) messages.push_back({clock, unsent[i] * link.bytes_per_pixel, i});
      continue;
    }
    if (via != Dispatcher::Via::Own) clock += 2 * link.latency_ms;  // asked the master
    const SimDevice& d = devices[i];
    std::vector<uint32_t> batch{id};  // a launch: its own list's remaining items too
    if (d.launch_ms > 0 && via == Dispatcher::Via::Own)
      for (size_t k = dispatch.pending(int(i)).size(); k > 0; --k)
        if (dispatch.next(int(i), id)) batch.push_back(id);
    std::vector<double> c(batch.size());
    double total = 0;
    for (size_t k = 0; k < batch.size(); ++k)
      total += c[k] = std::max(0.0, cost(dispatch.items()[batch[k]])) *
                      (1 + d.item_noise * symmetric_unit(rng));
    const double fixed = d.item_overhead_ms + d.launch_ms;
    const double start = clock + fixed;
    const double slow = d.contention > 0 ? 1 + d.contention * (at_work(clock) - 1) : 1.0;
    const double dt = fixed + run_time(start, total, d.speed * frame_factor[i] / slow,
                                       d.change_at_ms, d.speed_after * frame_factor[i] / slow);
    DeviceFrameStats& dev = stats.devices[i];
    for (size_t k = 0; k < batch.size(); ++k) {
      const WorkItem& item = dispatch.items()[batch[k]];
      const double w = dispatch.weight(batch[k]);
      const double share = batch.size() == 1 ? dt
                           : total > 0       ? dt * c[k] / total
                                             : dt / double(batch.size());
      dev.items.push_back(ItemReport{item, share, w, share, batch[k]});
      dev.samples += w;
      dev.pixels += double(item.rect.area());
      if (batched_results)
        unsent[i] += double(item.rect.area());
      else
        messages.push_back({clock + dt, double(item.rect.area()) * link.bytes_per_pixel, i});
    }
    dev.time_ms = dev.busy_ms = clock + dt;
    ready.push({clock + dt, i});
  }
  for (const DeviceFrameStats& dev : stats.devices)
    out.frame_ms = std::max(out.frame_ms, dev.time_ms);
  if (link.active()) out.frame_ms = std::max(out.frame_ms, last_arrival(messages, n, link));
  return out;
}

std::vector<SimFrame> simulate_run(
    Balancer& balancer, const FrameShape& shape,
    const std::function<std::vector<SimDevice>(int frame)>& devices_at, const CostFn& cost,
    int frames, uint64_t seed, const SimLink& link) {
  std::vector<SimFrame> run;
  for (int f = 0; f < frames; ++f) {
    SimFrame sf =
        simulate_linked(balancer.plan(shape, f), shape, devices_at(f), cost, link, f, seed);
    balancer.update(sf.stats);
    run.push_back(std::move(sf));
  }
  return run;
}

}  // namespace multiray::balance
