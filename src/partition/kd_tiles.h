// A k-d tree over a grid of tiles, after Bruder, Frey & Ertl, "Prediction-based load
// balancing and resolution tuning for interactive volume raycasting" (Visual Informatics
// 1(2), 2017), §6.2: every node cuts its rectangle of tiles in two, along its longer side,
// at the tile boundary where the cost on the first side best matches the summed shares of
// the devices on that side. Each leaf is one device's rectangle.
#pragma once

#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// A grid of `width`×`height` tiles and the cost of each, row-major:
// cost[ty · width + tx]. Costs are in any unit (predicted ms, samples, pixels); negative
// and non-finite costs count as 0.
struct TileCosts {
  int width = 0, height = 0;
  std::vector<double> cost;
};

// One rectangle per share, in tile units ([x0, x1) × [y0, y1) of the grid), which
// together cover every tile exactly once. Devices are split recursively into the first
// half (count / 2, rounded down) and the rest; a node cuts its rectangle along its longer
// side (columns on ties) at the tile boundary minimising |cost of the first part −
// total · (first half's share sum) / (node's share sum)|, the first such boundary on
// ties. A node whose rectangle costs nothing splits tile counts instead. A side whose
// shares sum to 0 gets an empty rectangle. Shares that are negative or not finite count as
// 0; if none is positive, all count as equal.
//
// Each cut misses its target by at most half the cost of one row or column of tiles of
// the node's rectangle. Throws std::invalid_argument if `shares` is empty, a side is
// negative, or cost.size() != width · height. O(tiles + devices · (width + height)).
std::vector<Rect> kd_split_tiles(const TileCosts& grid, const std::vector<double>& shares);

}  // namespace multiray::balance
