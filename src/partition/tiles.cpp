#include "partition/tiles.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace multiray::balance {

std::vector<Rect> make_tiles(int width, int height, int tile) {
  if (tile < 1) throw std::invalid_argument("tile size must be >= 1, got " + std::to_string(tile));
  std::vector<Rect> out;
  if (width <= 0 || height <= 0) return out;
  out.reserve(size_t((width + tile - 1) / tile) * size_t((height + tile - 1) / tile));
  // 64-bit steps: y + tile must not overflow for huge tile sizes.
  for (int64_t y = 0; y < height; y += tile)
    for (int64_t x = 0; x < width; x += tile)
      out.push_back(Rect{int(x), int(y), int(std::min<int64_t>(x + tile, width)),
                         int(std::min<int64_t>(y + tile, height))});
  return out;
}

}  // namespace multiray::balance
