// The one executor of a Plan. Every renderer that runs a Plan — multiray's engine, the
// simulator, another program linking multiray::balance — hands out items through this
// class, so what the simulator predicts is what the engine does, by construction.
//
// Dispatch rules, per request of a device:
//   1. its own list (Plan::assigned[device]), front first;
//   2. when that is empty, `Plan::batch` items from the front of the shared queue become
//      its own (not started yet), then rule 1;
//   3. when both are empty and Plan::steal is set, the LAST not-started item of the device
//      with the most not-started work (item weight: pixels × pixel_weight; > 0; lowest
//      index on ties).
// A device the plan leaves out (Plan::resting) gets nothing by any rule; one in
// Plan::no_steal nothing by rule 3.
// An item handed out by next() is started: nobody can steal it any more. Items moved into
// a device's own list by prefetch() are not started and stay stealable, so a device behind
// a slow link can hold k items in flight without keeping them from idle devices.
//
// Thread-safe: every member may be called concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "balance/plan.h"

namespace multiray::balance {

class Dispatcher {
 public:
  // Items are numbered in Plan::all_items() order (device lists, then the shared queue);
  // ItemReport::id and items() use these numbers. `shape` gives the item weights.
  Dispatcher(const Plan& plan, const FrameShape& shape);

  // How an item reached its device: its own list (assigned, or pulled earlier in a batch),
  // a pull from the shared queue (one request to whoever holds the queue), or a steal.
  enum class Via { Own, Shared, Stolen };

  // Starts the next item for `device` by the rules above; false when nothing is left.
  // `via`, if given, says how the item came.
  bool next(int device, uint32_t& id, Via* via = nullptr);
  // Starts up to `max` items at once (one request, e.g. one network round trip); appends
  // their ids to `out` and returns how many.
  size_t next(int device, size_t max, std::vector<uint32_t>& out);
  // Moves up to `k` items from the shared queue into `device`'s own list without starting
  // them; returns how many. They are handed out by later next() calls of this device,
  // unless stolen first.
  size_t prefetch(int device, size_t k);
  // Not-started items of `device`'s own list, front first.
  std::vector<uint32_t> pending(int device) const;
  // Removes and returns `device`'s not-started items (e.g. a device that failed).
  std::vector<uint32_t> take_remaining(int device);

  const std::vector<WorkItem>& items() const { return items_; }
  // Plan::pull_on_ready of the plan being run.
  bool pull_on_ready() const { return pull_on_ready_; }
  double weight(uint32_t id) const { return weight_[id]; }
  // Device that started item `id`, or -1.
  int taken_by(uint32_t id) const;
  // Items taken by stealing so far.
  int stolen() const;

 private:
  // Requires mutex_ held. Grows the per-device tables for an index the plan did not name.
  std::deque<uint32_t>& own(size_t device);
  void pull_shared(size_t device, size_t k);
  bool steal(uint32_t& id);

  mutable std::mutex mutex_;
  std::vector<WorkItem> items_;
  std::vector<double> weight_;
  std::vector<std::deque<uint32_t>> own_;
  std::vector<double> own_weight_;  // not-started weight per device
  std::deque<uint32_t> shared_;
  std::vector<int> taken_by_;
  size_t batch_ = 1;
  bool steal_ = false;
  bool pull_on_ready_ = false;
  std::vector<bool> resting_;   // Plan::resting: these devices get nothing
  std::vector<bool> no_steal_;  // Plan::no_steal
  int stolen_ = 0;
};

}  // namespace multiray::balance
