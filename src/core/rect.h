// A half-open rectangle of pixels [x0, x1) x [y0, y1) in one view. The balancing library
// has its own identical struct (it depends on nothing); the engine converts between them.
#pragma once

#include <cstdint>

namespace multiray {

struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int64_t area() const { return x1 > x0 && y1 > y0 ? int64_t(x1 - x0) * (y1 - y0) : 0; }
};

}  // namespace multiray
