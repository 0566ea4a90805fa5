#include "balance/row_density.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace multiray::balance {

RowDensity::RowDensity(const WeightMap& base)
    : base_(base),
      value_(size_t(base.views()) * size_t(base.height()), 0.0),
      weight_(value_.size(), 0.0) {}

void RowDensity::add(const WorkItem& item, double value) {
  if (!std::isfinite(value) || value < 0) return;
  if (item.view < 0 || item.view >= base_.views()) return;
  const double item_base = base_.sum(item);
  if (!(item_base > 0)) return;
  const int y0 = std::max(item.rect.y0, 0), y1 = std::min(item.rect.y1, base_.height());
  for (int y = y0; y < y1; ++y) {
    const double row_base =
        base_.sum(WorkItem{Rect{item.rect.x0, y, item.rect.x1, y + 1}, item.view});
    const size_t cell = size_t(item.view) * size_t(base_.height()) + size_t(y);
    value_[cell] += value * row_base / item_base;
    weight_[cell] += row_base;
  }
  total_value_ += value;
  total_base_ += item_base;
}

std::vector<double> RowDensity::density(double fallback) const {
  std::vector<double> d(value_.size(), fallback);
  for (size_t c = 0; c < d.size(); ++c)
    if (weight_[c] > 0) d[c] = value_[c] / weight_[c];
  return d;
}

double RowDensity::mean(double fallback) const {
  return total_base_ > 0 ? total_value_ / total_base_ : fallback;
}

std::vector<double> flat_row_weights(const WeightMap& map) {
  std::vector<double> w(size_t(map.views()) * size_t(map.height()));
  for (int v = 0; v < map.views(); ++v)
    for (int y = 0; y < map.height(); ++y)
      w[size_t(v) * size_t(map.height()) + size_t(y)] = map.row_sum(v, y);
  return w;
}

}  // namespace multiray::balance
