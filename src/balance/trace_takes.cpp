#include "balance/trace_takes.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "balance/balancer.h"

namespace multiray::balance::calib {

namespace {

bool same_item(const WorkItem& a, const WorkItem& b) {
  return a.view == b.view && a.rect.x0 == b.rect.x0 && a.rect.y0 == b.rect.y0 &&
         a.rect.x1 == b.rect.x1 && a.rect.y1 == b.rect.y1;
}

// The frame's origins from `plan` (its items numbered as the Dispatcher numbers them:
// device lists, then the shared queue); false when a recorded item is not in it as
// recorded.
bool from_plan(const Plan& plan, const FrameStats& fs, std::vector<std::vector<bool>>& own) {
  std::vector<WorkItem> items;
  std::vector<size_t> owner;
  for (size_t d = 0; d < plan.assigned.size(); ++d)
    for (const WorkItem& it : plan.assigned[d]) items.push_back(it), owner.push_back(d);
  for (const WorkItem& it : plan.shared) items.push_back(it), owner.push_back(fs.devices.size());
  for (size_t d = 0; d < fs.devices.size(); ++d) {
    const std::vector<ItemReport>& list = fs.devices[d].items;
    own[d].assign(list.size(), false);
    for (size_t k = 0; k < list.size(); ++k) {
      const uint32_t id = list[k].id;
      if (id >= items.size() || !same_item(items[id], list[k].item)) return false;
      own[d][k] = owner[id] == d;
    }
  }
  return true;
}

// Without the plan: a device's own items are the leading run of consecutive ids.
void from_ids(const FrameStats& fs, std::vector<std::vector<bool>>& own) {
  for (size_t d = 0; d < fs.devices.size(); ++d) {
    const std::vector<ItemReport>& list = fs.devices[d].items;
    own[d].assign(list.size(), false);
    for (size_t k = 0; k < list.size(); ++k)
      own[d][k] = k == 0 || (own[d][k - 1] && list[k].id == list[k - 1].id + 1);
  }
}

}  // namespace

Origins item_origins(const Trace& trace) {
  Origins out;
  const size_t n = trace.devices.size();
  std::unique_ptr<Balancer> balancer;
  try {
    balancer = make_balancer(trace.balancer, int(n));
  } catch (const std::invalid_argument&) {
    // Not a balancer this build knows: every frame falls back on the ids.
  }
  for (const FrameStats& fs : trace.frames) {
    std::vector<std::vector<bool>> own(n);
    bool matched = false;
    if (balancer) {
      try {
        matched = from_plan(balancer->plan(fs.shape, fs.frame), fs, own);
        balancer->update(fs);
      } catch (const std::exception&) {
        balancer.reset();  // the replay cannot go on: the rest by the ids
      }
    }
    if (!matched) from_ids(fs, own);
    out.matched += matched;
    out.own.push_back(std::move(own));
  }
  return out;
}

std::vector<Take> takes_of(const Trace& trace, const Origins& origins,
                           const std::vector<bool>& batching, size_t from) {
  std::vector<Take> out;
  for (size_t f = from; f < trace.frames.size(); ++f) {
    const FrameStats& fs = trace.frames[f];
    for (size_t d = 0; d < fs.devices.size(); ++d) {
      const std::vector<ItemReport>& list = fs.devices[d].items;
      const std::vector<bool>& own = origins.own[f][d];
      double start = fs.devices[d].time_ms;
      for (const ItemReport& r : list) start -= r.time_ms;
      start = std::max(start, 0.0);
      for (size_t k = 0, end; k < list.size(); k = end) {
        end = k + 1;
        if (batching[d] && own[k])
          while (end < list.size() && own[end]) ++end;
        int busy = 0;
        for (const DeviceFrameStats& other : fs.devices)
          busy += other.alive && !other.items.empty() && other.time_ms > start;
        out.push_back({f, d, k, end, k == 0, std::max(busy, 1)});
        for (size_t j = k; j < end; ++j) start += list[j].time_ms;
      }
    }
  }
  return out;
}

Trace net_trace_takes(const Trace& trace, const std::vector<bool>& batching,
                      const std::vector<double>& per_take, const std::vector<double>& first_take,
                      double contention) {
  Trace out = trace;
  const Origins origins = item_origins(trace);
  for (const Take& t : takes_of(trace, origins, batching, 0)) {
    std::vector<ItemReport>& list = out.frames[t.frame].devices[t.device].items;
    double total = 0;
    for (size_t k = t.begin; k < t.end; ++k) total += list[k].time_ms;
    const double fixed = per_take[t.device] + (t.first ? first_take[t.device] : 0.0);
    const double keep = total > 0 ? std::max(total - fixed, 0.0) / total : 0.0;
    const double slow = 1 + contention * (t.busy - 1);
    for (size_t k = t.begin; k < t.end; ++k)
      list[k].time_ms = list[k].busy_ms = list[k].time_ms * keep / slow;
  }
  return out;
}

}  // namespace multiray::balance::calib
