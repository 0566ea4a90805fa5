// A fixed list of work units handed out in order to whichever device asks: the simplest
// WorkSource (tests, re-rendering a failed device's share, single-device runs).
#pragma once

#include <mutex>
#include <vector>

#include "device/device.h"

namespace multiray {

class ListWorkSource : public WorkSource {
 public:
  explicit ListWorkSource(std::vector<WorkUnit> units) : units_(std::move(units)) {}
  bool next(int, WorkUnit& out) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pos_ >= units_.size()) return false;
    out = units_[pos_++];
    return true;
  }

 private:
  std::mutex mutex_;
  std::vector<WorkUnit> units_;
  size_t pos_ = 0;
};

}  // namespace multiray
