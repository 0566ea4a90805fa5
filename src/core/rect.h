// The pixel rectangle: one type for the whole project. It is multiray::balance's Rect
// (half-open [x0, x1) × [y0, y1) in one view), which is header-only and depends on nothing,
// so the core can use it without depending on the balancing library.
#pragma once

#include "partition/rect.h"

namespace multiray {

using balance::Rect;

}  // namespace multiray
