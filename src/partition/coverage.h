// The invariant every partition and plan must keep: each pixel of each view is rendered
// exactly once. Used by the tests, and cheap enough for an engine's debug checks.
#pragma once

#include <string>
#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// Empty if `items` cover every pixel of the `views` views of width×height exactly once;
// otherwise one line naming the first problem found (an item outside the frame, a pixel
// covered twice, a pixel never covered). Empty rects are allowed and ignored.
std::string coverage_error(const std::vector<WorkItem>& items, int width, int height, int views);

}  // namespace multiray::balance
