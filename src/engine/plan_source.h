// Executes a balance::Plan: the WorkSource the devices pull from during one frame.
// Dispatch rules (the same ones balance::simulate() models, so unit tests of balancers
// predict what the engine does):
//   1. a device takes the items of its own list, in order;
//   2. then pulls `batch` items at a time from the front of the shared queue;
//   3. then, if the plan allows stealing, takes the last not-started item of the device
//      with the most not-started work (pixels x weight).
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <vector>

#include "balance/balancer.h"
#include "device/device.h"
#include "device/work_list.h"

namespace multiray {

class PlanWorkSource : public WorkSource {
 public:
  // `pixel_weight` as in balance::FrameShape (empty: uniform). If `handed_out` is given,
  // the pixels of every item handed to a device are added to it (for progress display).
  PlanWorkSource(const balance::Plan& plan, const balance::FrameShape& shape,
                 std::atomic<int64_t>* handed_out = nullptr);

  bool next(int device, WorkUnit& out) override;

  const std::vector<balance::WorkItem>& items() const { return items_; }
  // Device that took item `id`, or -1 if nobody did.
  int taken_by(uint32_t id) const { return taken_by_[id]; }
  // Items still waiting in `device`'s own list (not started); removes them.
  std::vector<uint32_t> take_remaining(int device);
  // Counts of how items were obtained this frame.
  int stolen() const { return stolen_; }

 private:
  std::mutex mutex_;
  std::vector<balance::WorkItem> items_;
  std::vector<double> weight_;
  std::vector<std::deque<uint32_t>> own_;
  std::vector<double> own_weight_;
  std::deque<uint32_t> shared_;
  std::vector<int> taken_by_;
  int batch_ = 1;
  bool steal_ = false;
  int stolen_ = 0;
  std::atomic<int64_t>* handed_out_ = nullptr;
};

WorkUnit to_unit(const balance::WorkItem& item, uint32_t id);

}  // namespace multiray
