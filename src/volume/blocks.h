// Object-order empty-space skipping and cost estimation after Bruder, Frey & Ertl 2017,
// §4.1-4.2: the volume is cut into blocks of 16^3 voxels; each block keeps its value range and
// a 64-bin density histogram, built once when the volume loads. When the transfer
// function changes, each block's opacity histogram and maximum opacity are derived from
// those (block_opacity), without touching the voxels again: a block whose maximum
// opacity is 0 is empty and can be skipped, and the opacity histograms feed the cost
// model.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "volume/transfer_function.h"
#include "volume/volume.h"

namespace multiray {

constexpr int kBlockSize = 16;    // voxels per block edge (the last block per axis may be
                                  // smaller)
constexpr int kDensityBins = 64;  // per block, over [volume.min_value, volume.max_value]
constexpr int kOpacityBins = 16;  // per block, over opacity [0, 1]

struct VolumeBlocks {
  int bx = 0, by = 0, bz = 0;  // blocks per axis: ceil(n / kBlockSize)
  // Per block, index (z * by + y) * bx + x: the value range over the block's voxels plus a
  // one-voxel apron on each side (clipped to the grid), so every trilinear sample inside
  // the block's cells lies within it.
  std::vector<float> min_value, max_value;
  // Per block: how many of its own voxels (no apron) fall in each of kDensityBins equal
  // bins of [volume.min_value, volume.max_value] (the maximum goes into the last bin).
  std::vector<std::array<uint32_t, kDensityBins>> density;

  size_t count() const { return size_t(bx) * size_t(by) * size_t(bz); }
  size_t index(int x, int y, int z) const {
    return (size_t(z) * size_t(by) + size_t(y)) * size_t(bx) + size_t(x);
  }
};

// First voxel and voxel count of block `b` along an axis of `n` voxels.
inline int block_begin(int b) { return b * kBlockSize; }
inline int block_length(int b, int n) {
  return n - b * kBlockSize < kBlockSize ? n - b * kBlockSize : kBlockSize;
}

// Builds the blocks of `volume` (parallel over blocks, oneTBB).
VolumeBlocks build_blocks(const Volume& volume);

// Value interval [lo, hi] of density bin `bin` of `volume` (bin edges of
// [min_value, max_value]; a constant volume has every bin at that value).
std::array<float, 2> density_bin_range(const Volume& volume, int bin);

struct BlockOpacity {
  // Per block: the fraction of the block's own voxels whose opacity falls in each of
  // kOpacityBins equal bins of [0, 1] (opacity 1 in the last bin). Each voxel's opacity is
  // bounded above by the transfer function's maximum over its density bin (within the
  // block's range), so it is an estimate that errs towards opaque.
  std::vector<std::array<float, kOpacityBins>> histogram;
  // Per block: exact maximum opacity of the transfer function over [min_value,
  // max_value] of the block (interior points included). 0 iff the block is empty.
  std::vector<float> max_opacity;

  bool empty(size_t block) const { return max_opacity[block] == 0; }
};

// Derives the opacity data from `blocks` for `tf`, which must be in data units
// (resolve() first; throws std::invalid_argument otherwise). Cost: O(blocks * bins), no
// voxel is read.
BlockOpacity block_opacity(const VolumeBlocks& blocks, const TransferFunction& tf,
                           const Volume& volume);

}  // namespace multiray
