// Per-line densities learnt from item reports: the "piecewise-linear CDF of last frame's
// reported areas and sample counts" of Harada's semi-static split, and the per-row cost
// model of the hybrid balancer. Lines are the image's rows or its columns, numbered flat
// over views: a row is cell view·height + y (views stacked), a column view·width + x
// (views side by side).
#pragma once

#include <vector>

#include "partition/weight_map.h"

namespace multiray::balance {

enum class LineAxis { rows, columns };

class LineDensity {
 public:
  // `base` says how an item's value spreads over its lines: in proportion to the base
  // weight (area for a uniform map, samples for a pixel_weight map).
  // `base` must outlive this object.
  explicit LineDensity(const WeightMap& base, LineAxis axis = LineAxis::rows);

  // Adds `value` (samples, cost, ...) measured over `item`. Ignored when the value is not
  // finite or negative, or the item has no base weight inside the frame.
  void add(const WorkItem& item, double value);

  // Per cell: value per unit of base weight; `fallback` for cells nothing was added to.
  std::vector<double> density(double fallback) const;
  // Value per unit of base weight over everything added (`fallback` if nothing was).
  double mean(double fallback) const;
  bool empty() const { return !(total_base_ > 0); }

 private:
  const WeightMap& base_;
  LineAxis axis_;
  std::vector<double> value_, weight_;  // per cell
  double total_value_ = 0, total_base_ = 0;
};

// Base weight of every flat row of `map`: its row sums, views·height values.
std::vector<double> flat_row_weights(const WeightMap& map);
// Base weight of every flat column of `map`: its column sums, views·width values.
std::vector<double> flat_column_weights(const WeightMap& map);

}  // namespace multiray::balance
