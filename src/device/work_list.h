// A fixed list of work items handed out in order to whichever device asks: the simplest
// WorkSource (tests, re-rendering a failed device's share, timing a device alone).
#pragma once

#include <map>
#include <mutex>
#include <vector>

#include "device/device.h"

namespace multiray {

class ListWorkSource : public WorkSource {
 public:
  // Item i gets id ids[i] (default: i).
  explicit ListWorkSource(std::vector<WorkItem> items, std::vector<uint32_t> ids = {})
      : items_(std::move(items)), ids_(std::move(ids)) {
    if (ids_.empty())
      for (uint32_t i = 0; i < items_.size(); ++i) ids_.push_back(i);
    for (size_t i = 0; i < items_.size(); ++i) by_id_[ids_[i]] = i;
  }
  bool next(int, uint32_t& id) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pos_ >= items_.size()) return false;
    id = ids_[pos_++];
    return true;
  }
  // The whole list is its one device's: every item not yet started is that device's own.
  size_t pending(int) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size() - pos_;
  }
  const WorkItem& item(uint32_t id) const override { return items_[by_id_.at(id)]; }

 private:
  mutable std::mutex mutex_;
  std::vector<WorkItem> items_;
  std::vector<uint32_t> ids_;
  std::map<uint32_t, size_t> by_id_;
  size_t pos_ = 0;
};

}  // namespace multiray
