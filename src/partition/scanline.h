// Ranges of pixels in scanline order, turned into rects. Shuffled strips, the CDF splitter
// and the hybrid balancer all cut the image as a 1-D sequence of pixels; this is where
// those cuts become WorkItems.
#pragma once

#include <cstdint>
#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// Appends the pixels [begin, end) of one view, in scanline order (pixel index
// y*width + x), as at most three rects: a partial first row, a block of whole rows and a
// partial last row, in that order. Nothing is appended for an empty range. Requires
// width > 0 and 0 <= begin <= end <= width*height.
void append_scanline_rects(int width, int64_t begin, int64_t end, int view,
                           std::vector<WorkItem>& out);

// The same over all views laid end to end ("flat" index (view*height + y)*width + x): a
// range that crosses a view boundary gives rects in each view it touches.
void append_flat_range(int width, int height, int64_t begin, int64_t end,
                       std::vector<WorkItem>& out);

// The same in column order over views laid side by side (flat index
// (view*width + x)*height + y): per view, at most a partial first column, a block of
// whole columns and a partial last column (vertical bands, as Harada's split).
void append_flat_column_range(int width, int height, int64_t begin, int64_t end,
                              std::vector<WorkItem>& out);

}  // namespace multiray::balance
