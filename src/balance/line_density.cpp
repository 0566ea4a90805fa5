#include "balance/line_density.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace multiray::balance {

namespace {

int line_count(const WeightMap& m, LineAxis axis) {
  return axis == LineAxis::rows ? m.height() : m.width();
}

}  // namespace

LineDensity::LineDensity(const WeightMap& base, LineAxis axis)
    : base_(base),
      axis_(axis),
      value_(size_t(base.views()) * size_t(line_count(base, axis)), 0.0),
      weight_(value_.size(), 0.0) {}

void LineDensity::add(const WorkItem& item, double value) {
  if (!std::isfinite(value) || value < 0) return;
  if (item.view < 0 || item.view >= base_.views()) return;
  const double item_base = base_.sum(item);
  if (!(item_base > 0)) return;
  const bool rows = axis_ == LineAxis::rows;
  const int lines = line_count(base_, axis_);
  const int l0 = std::max(rows ? item.rect.y0 : item.rect.x0, 0);
  const int l1 = std::min(rows ? item.rect.y1 : item.rect.x1, lines);
  for (int l = l0; l < l1; ++l) {
    const Rect line = rows ? Rect{item.rect.x0, l, item.rect.x1, l + 1}
                           : Rect{l, item.rect.y0, l + 1, item.rect.y1};
    const double line_base = base_.sum(WorkItem{line, item.view});
    const size_t cell = size_t(item.view) * size_t(lines) + size_t(l);
    value_[cell] += value * line_base / item_base;
    weight_[cell] += line_base;
  }
  total_value_ += value;
  total_base_ += item_base;
}

std::vector<double> LineDensity::density(double fallback) const {
  std::vector<double> d(value_.size(), fallback);
  for (size_t c = 0; c < d.size(); ++c)
    if (weight_[c] > 0) d[c] = value_[c] / weight_[c];
  return d;
}

double LineDensity::mean(double fallback) const {
  return total_base_ > 0 ? total_value_ / total_base_ : fallback;
}

std::vector<double> flat_row_weights(const WeightMap& map) {
  std::vector<double> w(size_t(map.views()) * size_t(map.height()));
  for (int v = 0; v < map.views(); ++v)
    for (int y = 0; y < map.height(); ++y)
      w[size_t(v) * size_t(map.height()) + size_t(y)] = map.row_sum(v, y);
  return w;
}

std::vector<double> flat_column_weights(const WeightMap& map) {
  std::vector<double> w(size_t(map.views()) * size_t(map.width()));
  for (int v = 0; v < map.views(); ++v)
    for (int x = 0; x < map.width(); ++x)
      w[size_t(v) * size_t(map.width()) + size_t(x)] = map.column_sum(v, x);
  return w;
}

}  // namespace multiray::balance
