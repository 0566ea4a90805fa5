// The devices' WorkSource for one frame: balance::Dispatcher (the plan's dispatch rules,
// shared with the simulator) plus a count of the pixels handed out, for progress display.
#pragma once

#include <atomic>

#include "balance/dispatcher.h"
#include "device/device.h"

namespace multiray {

class DispatchSource : public WorkSource {
 public:
  // If `handed_out` is given, the pixels of every item started are added to it.
  DispatchSource(const balance::Plan& plan, const balance::FrameShape& shape,
                 std::atomic<int64_t>* handed_out = nullptr)
      : dispatch_(plan, shape), handed_out_(handed_out) {}

  bool next(int device, uint32_t& id) override {
    if (!dispatch_.next(device, id)) return false;
    if (handed_out_) *handed_out_ += item(id).rect.area();
    return true;
  }
  size_t prefetch(int device, size_t k) override { return dispatch_.prefetch(device, k); }
  size_t pending(int device) const override { return dispatch_.pending(device).size(); }
  bool pull_on_ready() const override { return dispatch_.pull_on_ready(); }
  const WorkItem& item(uint32_t id) const override { return dispatch_.items()[id]; }

  balance::Dispatcher& dispatcher() { return dispatch_; }

 private:
  balance::Dispatcher dispatch_;
  std::atomic<int64_t>* handed_out_;
};

}  // namespace multiray
