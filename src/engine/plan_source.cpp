#include "engine/plan_source.h"

namespace multiray {

WorkUnit to_unit(const balance::WorkItem& item, uint32_t id) {
  WorkUnit u;
  u.rect = PixelRect{item.rect.x0, item.rect.y0, item.rect.x1, item.rect.y1};
  u.view = uint32_t(item.view);
  u.id = id;
  return u;
}

namespace {
double item_weight(const balance::WorkItem& it, const balance::FrameShape& shape) {
  if (shape.pixel_weight.empty()) return double(it.rect.area());
  double w = 0;
  const size_t base = size_t(it.view) * size_t(shape.width) * size_t(shape.height);
  for (int y = it.rect.y0; y < it.rect.y1; ++y)
    for (int x = it.rect.x0; x < it.rect.x1; ++x)
      w += shape.pixel_weight[base + size_t(y) * size_t(shape.width) + size_t(x)];
  return w;
}
}  // namespace

PlanWorkSource::PlanWorkSource(const balance::Plan& plan, const balance::FrameShape& shape,
                               std::atomic<int64_t>* handed_out)
    : own_(plan.assigned.size()),
      own_weight_(plan.assigned.size(), 0.0),
      batch_(std::max(1, plan.batch)),
      steal_(plan.steal) {
  auto add = [&](const balance::WorkItem& it) {
    items_.push_back(it);
    weight_.push_back(item_weight(it, shape));
    return uint32_t(items_.size() - 1);
  };
  for (size_t d = 0; d < plan.assigned.size(); ++d)
    for (const auto& it : plan.assigned[d]) {
      const uint32_t id = add(it);
      own_[d].push_back(id);
      own_weight_[d] += weight_[id];
    }
  for (const auto& it : plan.shared) shared_.push_back(add(it));
  taken_by_.assign(items_.size(), -1);
  handed_out_ = handed_out;
}

bool PlanWorkSource::next(int device, WorkUnit& out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (device < 0) return false;
  if (size_t(device) >= own_.size()) {
    own_.resize(size_t(device) + 1);
    own_weight_.resize(size_t(device) + 1, 0.0);
  }
  auto& mine = own_[size_t(device)];
  if (mine.empty() && !shared_.empty()) {
    for (int i = 0; i < batch_ && !shared_.empty(); ++i) {
      mine.push_back(shared_.front());
      own_weight_[size_t(device)] += weight_[shared_.front()];
      shared_.pop_front();
    }
  }
  uint32_t id;
  if (!mine.empty()) {
    id = mine.front();
    mine.pop_front();
    own_weight_[size_t(device)] -= weight_[id];
  } else if (steal_) {
    size_t victim = own_.size();
    double most = 0;
    for (size_t d = 0; d < own_.size(); ++d)
      if (!own_[d].empty() && own_weight_[d] > most) most = own_weight_[d], victim = d;
    if (victim == own_.size()) return false;
    id = own_[victim].back();
    own_[victim].pop_back();
    own_weight_[victim] -= weight_[id];
    ++stolen_;
  } else {
    return false;
  }
  taken_by_[id] = device;
  if (handed_out_) *handed_out_ += items_[id].rect.area();
  out = to_unit(items_[id], id);
  return true;
}

std::vector<uint32_t> PlanWorkSource::take_remaining(int device) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<uint32_t> out;
  if (size_t(device) >= own_.size()) return out;
  out.assign(own_[size_t(device)].begin(), own_[size_t(device)].end());
  own_[size_t(device)].clear();
  own_weight_[size_t(device)] = 0;
  return out;
}

}  // namespace multiray
