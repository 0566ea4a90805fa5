#include "balance/region.h"

#include <algorithm>
#include <stdexcept>

namespace multiray::balance {

namespace {
Rect clip(const Rect& r, const FrameShape& shape) {
  return Rect{std::max(r.x0, 0), std::max(r.y0, 0), std::min(r.x1, shape.width),
              std::min(r.y1, shape.height)};
}
WorkItem moved(WorkItem it, int dx, int dy) {
  it.rect = Rect{it.rect.x0 + dx, it.rect.y0 + dy, it.rect.x1 + dx, it.rect.y1 + dy};
  return it;
}
}  // namespace

FrameShape crop_shape(const FrameShape& shape, const Rect& region) {
  validate_shape(shape);
  const Rect r = clip(region, shape);
  if (r.empty()) throw std::invalid_argument("the region to balance is empty");
  FrameShape out;
  out.width = r.width();
  out.height = r.height();
  out.views = shape.views;
  if (shape.weighted()) {
    out.pixel_weight.reserve(size_t(out.pixels()));
    for (int v = 0; v < shape.views; ++v)
      for (int y = r.y0; y < r.y1; ++y) {
        const auto row = shape.pixel_weight.begin() +
                         ptrdiff_t((int64_t(v) * shape.height + y) * shape.width + r.x0);
        out.pixel_weight.insert(out.pixel_weight.end(), row, row + r.width());
      }
  }
  return out;
}

RegionBalancer::RegionBalancer(std::unique_ptr<Balancer> inner, Rect region)
    : inner_(std::move(inner)), region_(region) {
  if (!inner_) throw std::invalid_argument("RegionBalancer needs a balancer");
}

Plan RegionBalancer::plan(const FrameShape& shape, int frame) {
  planned_ = clip(region_, shape);
  Plan p = inner_->plan(crop_shape(shape, planned_), frame);
  for (auto& list : p.assigned)
    for (WorkItem& it : list) it = moved(it, planned_.x0, planned_.y0);
  for (WorkItem& it : p.shared) it = moved(it, planned_.x0, planned_.y0);
  return p;
}

void RegionBalancer::update(const FrameStats& stats) {
  FrameStats local = stats;
  if (!planned_.empty() && stats.shape.width >= planned_.x1 && stats.shape.height >= planned_.y1)
    local.shape = crop_shape(stats.shape, planned_);
  for (DeviceFrameStats& d : local.devices) {
    std::vector<ItemReport> inside;
    for (const ItemReport& r : d.items) {
      const Rect& q = r.item.rect;
      if (q.x0 < planned_.x0 || q.y0 < planned_.y0 || q.x1 > planned_.x1 || q.y1 > planned_.y1)
        continue;
      ItemReport m = r;
      m.item = moved(r.item, -planned_.x0, -planned_.y0);
      inside.push_back(m);
    }
    d.items = std::move(inside);
  }
  inner_->update(local);
}

}  // namespace multiray::balance
