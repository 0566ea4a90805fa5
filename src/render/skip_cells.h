// Empty-space skipping finer than Bruder et al.'s 16^3-voxel blocks, for the CPU
// raycaster: cells of 4^3 voxels, each with the value range over the cell and a one-voxel
// apron (so every trilinear sample inside the cell lies within it), and per transfer
// function the largest opacity the table gives over that range. Inside a block that is not
// empty, the raycaster walks these cells and skips those whose opacity is exactly 0: on
// thin structures (the aneurism's vessels) most of a non-empty block is empty. Skipping
// drops only samples of opacity exactly 0, so the image is unchanged. The blocks stay
// Bruder's: they feed the cost model and the OpenCL raycaster.
#pragma once

#include <cstddef>
#include <vector>

#include "volume/transfer_function.h"
#include "volume/volume.h"

namespace multiray {

inline constexpr int kSkipCell =
    4;  // voxels per cell edge (the last cell per axis may be smaller)

struct SkipCells {
  int cx = 0, cy = 0, cz = 0;               // cells per axis: ceil(n / kSkipCell)
  std::vector<float> min_value, max_value;  // per cell, apron included; index as below
  size_t count() const { return size_t(cx) * size_t(cy) * size_t(cz); }
};

// Bytes per voxel the cells take (two floats per 64 voxels), counted when a volume loads.
inline constexpr double kSkipCellBytesPerVoxel = 2.0 * sizeof(float) / 64;

// The cells of `v` (parallel over slabs of cells, oneTBB).
SkipCells build_skip_cells(const Volume& v);

// Per cell of `c`: the largest opacity (alpha) of `table`'s entries that interpolation
// between the cell's smallest and largest value reads, with one entry of margin for
// rounding: the rule of the blocks' maximum (volume_raycaster.cpp), answered by a
// range-maximum table over the entries, O(entries log entries + cells).
std::vector<float> cell_max_opacity(const SkipCells& c, const TransferTable& table);

}  // namespace multiray
