// The voxels as the CPU raycaster reads them: in the file's own type (1 or 2 bytes a voxel)
// when every value fits it exactly, as it does for the 8- and 16-bit files the loaders
// read; Volume::values' floats otherwise. A ray's trilinear fetches then move a quarter or
// half of the bytes they moved as floats (most of a volume frame's time is these fetches:
// docs/benchmarks.md), and each fetch still yields the very float Volume::values holds
// (an integer of 8 or 16 bits is exact in a float), so the images do not change by a bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "volume/volume.h"

namespace multiray {

struct VoxelGrid {
  enum class Store { u8, i8, u16, i16, f32 };
  Store store = Store::f32;
  std::vector<uint8_t> bytes;  // the narrow copy, x fastest (empty for f32: use values)

  template <class T>
  const T* as() const {
    return reinterpret_cast<const T*>(bytes.data());
  }
};

// Bytes per voxel the narrow copy may take (its largest, 16-bit, case), counted when a
// volume loads (VolumeLoadOptions::kept_bytes_per_voxel).
inline constexpr uint64_t kVoxelGridBytesPerVoxel = 2;

// The narrow copy of `v` in its voxel type, or f32 (no copy) when some value does not fit
// that type exactly.
VoxelGrid make_voxel_grid(const Volume& v);

}  // namespace multiray
