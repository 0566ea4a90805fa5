#include "balance/dispatcher.h"

#include <algorithm>

#include "partition/weight_map.h"

namespace multiray::balance {

Dispatcher::Dispatcher(const Plan& plan, const FrameShape& shape)
    : own_(plan.assigned.size()),
      own_weight_(plan.assigned.size(), 0.0),
      batch_(size_t(std::max(1, plan.batch))),
      steal_(plan.steal),
      pull_on_ready_(plan.pull_on_ready),
      resting_(plan.resting),
      no_steal_(plan.no_steal) {
  const WeightMap map(shape.width, shape.height, shape.views, shape.pixel_weight);
  auto add = [&](const WorkItem& it) {
    items_.push_back(it);
    weight_.push_back(map.sum(it));
    return uint32_t(items_.size() - 1);
  };
  for (size_t d = 0; d < plan.assigned.size(); ++d)
    for (const WorkItem& it : plan.assigned[d]) {
      const uint32_t id = add(it);
      own_[d].push_back(id);
      own_weight_[d] += weight_[id];
    }
  for (const WorkItem& it : plan.shared) shared_.push_back(add(it));
  taken_by_.assign(items_.size(), -1);
}

std::deque<uint32_t>& Dispatcher::own(size_t device) {
  if (device >= own_.size()) {
    own_.resize(device + 1);
    own_weight_.resize(device + 1, 0.0);
  }
  return own_[device];
}

void Dispatcher::pull_shared(size_t device, size_t k) {
  auto& mine = own(device);
  for (size_t i = 0; i < k && !shared_.empty(); ++i) {
    mine.push_back(shared_.front());
    own_weight_[device] += weight_[shared_.front()];
    shared_.pop_front();
  }
}

bool Dispatcher::steal(uint32_t& id) {
  size_t victim = own_.size();
  double most = 0;
  for (size_t d = 0; d < own_.size(); ++d)
    if (!own_[d].empty() && own_weight_[d] > most) most = own_weight_[d], victim = d;
  if (victim == own_.size()) return false;
  id = own_[victim].back();
  own_[victim].pop_back();
  own_weight_[victim] -= weight_[id];
  ++stolen_;
  return true;
}

bool Dispatcher::next(int device, uint32_t& id, Via* via) {
  if (device < 0 || (size_t(device) < resting_.size() && resting_[size_t(device)])) return false;
  const size_t d = size_t(device);
  std::lock_guard<std::mutex> lock(mutex_);
  auto& mine = own(d);
  Via how = Via::Own;
  if (mine.empty() && !shared_.empty()) {
    pull_shared(d, batch_);
    how = Via::Shared;
  }
  if (!mine.empty()) {
    id = mine.front();
    mine.pop_front();
    own_weight_[d] -= weight_[id];
  } else if (steal_ && !(d < no_steal_.size() && no_steal_[d]) && steal(id)) {
    how = Via::Stolen;
  } else {
    return false;
  }
  if (via) *via = how;
  taken_by_[id] = device;
  return true;
}

size_t Dispatcher::next(int device, size_t max, std::vector<uint32_t>& out) {
  size_t n = 0;
  for (uint32_t id; n < max && next(device, id); ++n) out.push_back(id);
  return n;
}

size_t Dispatcher::prefetch(int device, size_t k) {
  if (device < 0 || (size_t(device) < resting_.size() && resting_[size_t(device)])) return 0;
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t before = own(size_t(device)).size();
  pull_shared(size_t(device), k);
  return own_[size_t(device)].size() - before;
}

std::vector<uint32_t> Dispatcher::pending(int device) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (device < 0 || size_t(device) >= own_.size()) return {};
  return {own_[size_t(device)].begin(), own_[size_t(device)].end()};
}

std::vector<uint32_t> Dispatcher::take_remaining(int device) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (device < 0 || size_t(device) >= own_.size()) return {};
  std::vector<uint32_t> out(own_[size_t(device)].begin(), own_[size_t(device)].end());
  own_[size_t(device)].clear();
  own_weight_[size_t(device)] = 0;
  return out;
}

int Dispatcher::taken_by(uint32_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return id < taken_by_.size() ? taken_by_[id] : -1;
}

int Dispatcher::stolen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stolen_;
}

}  // namespace multiray::balance
