// Contiguous bands: the simplest screen split, one rect per device.
#pragma once

#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

enum class Axis {
  Rows,     // horizontal bands stacked top to bottom
  Columns,  // vertical bands left to right
};

// One rect per device (device 0 first): bands along `axis` whose sizes in rows (or
// columns) follow `ratios` by largest-remainder rounding (see apportion()). A device whose
// ratio rounds to 0 rows gets an empty rect. The rects tile the width×height image exactly
// once. Width or height <= 0 gives empty rects.
std::vector<Rect> split_bands(int width, int height, const std::vector<double>& ratios,
                              Axis axis = Axis::Rows);

}  // namespace multiray::balance
