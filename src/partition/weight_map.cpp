#include "partition/weight_map.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace multiray::balance {

WeightMap::WeightMap(int width, int height, int views, const std::vector<float>& pixel_weight)
    : width_(std::max(width, 0)), height_(std::max(height, 0)), views_(std::max(views, 0)) {
  const size_t pixels = size_t(width_) * size_t(height_) * size_t(views_);
  if (pixel_weight.empty()) return;
  if (pixel_weight.size() != pixels)
    throw std::invalid_argument(
        "pixel_weight has " + std::to_string(pixel_weight.size()) +
        " values, expected views*height*width = " + std::to_string(pixels));
  const size_t row = size_t(width_) + 1;
  table_.assign(size_t(views_) * (size_t(height_) + 1) * row, 0.0);
  for (int v = 0; v < views_; ++v) {
    double* base = &table_[size_t(v) * (size_t(height_) + 1) * row];
    const float* src = &pixel_weight[size_t(v) * size_t(width_) * size_t(height_)];
    for (int y = 0; y < height_; ++y) {
      double running = 0;
      for (int x = 0; x < width_; ++x) {
        const float w = src[size_t(y) * size_t(width_) + size_t(x)];
        running += std::isfinite(w) && w > 0 ? double(w) : 0.0;
        base[(size_t(y) + 1) * row + size_t(x) + 1] =
            base[size_t(y) * row + size_t(x) + 1] + running;
      }
    }
  }
}

double WeightMap::at(int view, int x, int y) const {
  const size_t row = size_t(width_) + 1;
  return table_[(size_t(view) * (size_t(height_) + 1) + size_t(y)) * row + size_t(x)];
}

double WeightMap::sum(const WorkItem& item) const {
  if (item.view < 0 || item.view >= views_) return 0;
  const int x0 = std::clamp(item.rect.x0, 0, width_), x1 = std::clamp(item.rect.x1, 0, width_);
  const int y0 = std::clamp(item.rect.y0, 0, height_), y1 = std::clamp(item.rect.y1, 0, height_);
  if (x1 <= x0 || y1 <= y0) return 0;
  if (uniform()) return double(x1 - x0) * double(y1 - y0);
  return at(item.view, x1, y1) - at(item.view, x0, y1) - at(item.view, x1, y0) +
         at(item.view, x0, y0);
}

double WeightMap::sum(const std::vector<WorkItem>& items) const {
  double s = 0;
  for (const WorkItem& item : items) s += sum(item);
  return s;
}

double WeightMap::row_sum(int view, int y) const {
  return sum(WorkItem{Rect{0, y, width_, y + 1}, view});
}

double WeightMap::column_sum(int view, int x) const {
  return sum(WorkItem{Rect{x, 0, x + 1, height_}, view});
}

double WeightMap::total() const {
  double s = 0;
  for (int v = 0; v < views_; ++v) s += sum(WorkItem{Rect{0, 0, width_, height_}, v});
  return s;
}

}  // namespace multiray::balance
