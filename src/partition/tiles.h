// Square tiles, the grain of on-demand queues (Seo et al.).
#pragma once

#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// Tiles of `tile`×`tile` pixels covering a width×height image, clipped at the right and
// bottom edges, listed in scanline order of tiles (row of tiles by row of tiles). Throws
// std::invalid_argument if `tile` < 1. Empty for an empty image.
std::vector<Rect> make_tiles(int width, int height, int tile);

}  // namespace multiray::balance
