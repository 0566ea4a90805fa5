// The CDF splitter: cut a 1-D sequence of weighted cells into consecutive pieces holding
// given shares of the total weight. As in Harada (GPU Pro 7, ch. 4, "Semi-static Load
// Balancing for Low Latency Ray Tracing on Heterogeneous Multiple GPUs") and Harada &
// Fujita (2014), the cumulative weight is treated as
// piecewise linear (each cell's weight spread evenly over it) and each cut is found by
// binary search in the prefix sums followed by linear interpolation inside the cell.
//
// Cells are usually image rows (weight = samples or estimated cost of the row), so a
// band split follows the work, not the area.
#pragma once

#include <cstdint>
#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// Cuts the unit range [0, cells·cell_size) into shares.size() consecutive ranges; range i
// is [cuts[i], cuts[i+1]) and holds share_i/Σshare of the total weight, up to rounding the
// cut to the nearest unit: each cut is within half a cell's weight of its target when
// cell_size is 1 and within one unit's worth otherwise. `cell_size` (>= 1) is how many
// units a cell spans (e.g. the image width, to cut a row sequence at pixel precision).
//
// Returns shares.size()+1 non-decreasing positions, the first 0 and the last
// cells·cell_size. A share of 0 gives an empty range. Negative or non-finite weights count
// as 0, and if the total weight is 0 the cells are weighted equally; shares are sanitised
// like apportion() ratios.
std::vector<int64_t> cdf_cuts(const std::vector<double>& cell_weight, int64_t cell_size,
                              const std::vector<double>& shares);

// Horizontal bands of a width×row_weight.size() image, one rect per device, cut at whole
// rows so that band i holds share_i of the row weights to within one row's weight
// (each of its two cuts is at most half a row off).
std::vector<Rect> cdf_split_rows(int width, const std::vector<double>& row_weight,
                                 const std::vector<double>& shares);

// Vertical bands cut at whole columns by `column_weight` (same contract as rows).
std::vector<Rect> cdf_split_columns(int height, const std::vector<double>& column_weight,
                                    const std::vector<double>& shares);

// Pixel-precise split of one view by a per-pixel weight (width·height values, row-major):
// device i gets the contiguous scanline range holding share_i of the weight, as at most
// three rects, within one pixel's weight of its target.
std::vector<std::vector<WorkItem>> cdf_split_pixels(int width, int height, int view,
                                                    const std::vector<double>& pixel_weight,
                                                    const std::vector<double>& shares);

}  // namespace multiray::balance
