// Sums of a per-pixel weight (samples per pixel, or a cost per pixel) over WorkItems in
// O(1), via one summed-area table per view.
#pragma once

#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

class WeightMap {
 public:
  // Unit weight everywhere on a 0×0 frame.
  WeightMap() = default;

  // `pixel_weight` holds views·height·width values (row-major per view, views in order),
  // or is empty for a weight of 1 per pixel (then no table is stored and sums are areas).
  // Negative and non-finite weights count as 0. Throws std::invalid_argument when the size
  // is neither 0 nor views·height·width.
  WeightMap(int width, int height, int views, const std::vector<float>& pixel_weight);

  // Weight inside `item`, clipped to the frame (0 for an item outside it or of a view
  // that does not exist).
  double sum(const WorkItem& item) const;
  double sum(const std::vector<WorkItem>& items) const;
  // Weight of row `y` of `view`.
  double row_sum(int view, int y) const;
  // Weight of column `x` of `view` (O(height) for a weighted map).
  double column_sum(int view, int x) const;
  double total() const;

  bool uniform() const { return table_.empty(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int views() const { return views_; }

 private:
  // table_[(view·(height+1) + y)·(width+1) + x] = weight of [0,x)×[0,y) in `view`.
  double at(int view, int x, int y) const;

  int width_ = 0, height_ = 0, views_ = 0;
  std::vector<double> table_;
};

}  // namespace multiray::balance
