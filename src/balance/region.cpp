#include "balance/region.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace multiray::balance {

namespace {
Rect clip(const Rect& r, const FrameShape& shape) {
  return Rect{std::max(r.x0, 0), std::max(r.y0, 0), std::min(r.x1, shape.width),
              std::min(r.y1, shape.height)};
}
Rect flip(const Rect& r) { return Rect{r.y0, r.x0, r.y1, r.x1}; }

// An item of the inner plan (region-local, maybe transposed, maybe one view) in frame
// coordinates.
WorkItem to_frame(WorkItem it, const Region& at) {
  const Rect r = at.transposed ? flip(it.rect) : it.rect;
  it.rect = Rect{r.x0 + at.rect.x0, r.y0 + at.rect.y0, r.x1 + at.rect.x0, r.y1 + at.rect.y0};
  if (at.view >= 0) it.view = at.view;
  return it;
}
// The inverse; false when the item lies outside the region.
bool to_region(WorkItem& it, const Region& at) {
  const Rect& q = it.rect;
  const Rect& a = at.rect;
  if (q.x0 < a.x0 || q.y0 < a.y0 || q.x1 > a.x1 || q.y1 > a.y1) return false;
  if (at.view >= 0 && it.view != at.view) return false;
  const Rect local{q.x0 - a.x0, q.y0 - a.y0, q.x1 - a.x0, q.y1 - a.y0};
  it.rect = at.transposed ? flip(local) : local;
  if (at.view >= 0) it.view = 0;
  return true;
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

FrameShape crop_shape(const FrameShape& shape, const Rect& region, int view) {
  if (view < 0 || view >= shape.views)
    throw std::invalid_argument("the view to balance is not in the frame");
  FrameShape out = crop_shape(shape, region);
  if (out.weighted()) {
    const auto first = out.pixel_weight.begin() + ptrdiff_t(int64_t(view) * out.pixels_per_view());
    out.pixel_weight = std::vector<float>(first, first + ptrdiff_t(out.pixels_per_view()));
  }
  out.views = 1;
  return out;
}

FrameShape transposed(const FrameShape& shape) {
  validate_shape(shape);
  FrameShape out = shape;
  std::swap(out.width, out.height);
  if (shape.weighted())
    for (int v = 0; v < shape.views; ++v) {
      const size_t base = size_t(int64_t(v) * shape.pixels_per_view());
      for (int y = 0; y < shape.height; ++y)
        for (int x = 0; x < shape.width; ++x)
          out.pixel_weight[base + size_t(x) * size_t(shape.height) + size_t(y)] =
              shape.pixel_weight[base + size_t(y) * size_t(shape.width) + size_t(x)];
    }
  return out;
}

RegionBalancer::RegionBalancer(std::unique_ptr<Balancer> inner, Region region)
    : inner_(std::move(inner)), region_(region) {
  if (!inner_) throw std::invalid_argument("RegionBalancer needs a balancer");
}

CutAxis RegionBalancer::cut_axis() const {
  const CutAxis inner = inner_->cut_axis();
  if (!region_.transposed || inner == CutAxis::none) return inner;
  return inner == CutAxis::rows ? CutAxis::columns : CutAxis::rows;
}

FrameShape RegionBalancer::inner_shape(const FrameShape& shape) const {
  FrameShape s = planned_.view >= 0 ? crop_shape(shape, planned_.rect, planned_.view)
                                    : crop_shape(shape, planned_.rect);
  return planned_.transposed ? transposed(s) : s;
}

Plan RegionBalancer::plan(const FrameShape& shape, int frame) {
  planned_ = region_;
  planned_.rect = clip(region_.rect, shape);
  Plan p = inner_->plan(inner_shape(shape), frame);
  for (auto& list : p.assigned)
    for (WorkItem& it : list) it = to_frame(it, planned_);
  for (WorkItem& it : p.shared) it = to_frame(it, planned_);
  return p;
}

void RegionBalancer::update(const FrameStats& stats) {
  FrameStats local = stats;
  const Rect& a = planned_.rect;
  const bool view_ok = planned_.view < 0 || planned_.view < stats.shape.views;
  if (!a.empty() && stats.shape.width >= a.x1 && stats.shape.height >= a.y1 && view_ok)
    local.shape = inner_shape(stats.shape);
  for (DeviceFrameStats& d : local.devices) {
    std::vector<ItemReport> inside;
    for (ItemReport r : d.items)
      if (to_region(r.item, planned_)) inside.push_back(r);
    d.items = std::move(inside);
  }
  inner_->update(local);
}

}  // namespace multiray::balance
