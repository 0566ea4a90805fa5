// The invariant every partition and plan must keep: each pixel of each view is rendered
// exactly once. Used by the tests, and cheap enough for an engine's debug checks.
#pragma once

#include <string>
#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// Empty if `items` cover every pixel of the `views` views of width×height exactly once;
// otherwise one line naming the first problem found (an inverted item, x1 < x0 or y1 < y0;
// an item outside the frame; a pixel covered twice; a pixel never covered, the first in
// row-major order, view by view). Empty rects (x1 == x0 or y1 == y0) are allowed and
// ignored. O(n log n) in the items, independent of the frame's size and view count.
std::string coverage_error(const std::vector<WorkItem>& items, int width, int height, int views);

}  // namespace multiray::balance
