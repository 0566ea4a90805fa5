// Scalar volumes for the raycaster (Bruder, Frey & Ertl 2017, "Prediction-based load
// balancing and resolution tuning for interactive volume raycasting"): a regular grid of
// samples read from NRRD or raw files, kept in the file's own units so transfer functions
// can speak in them (Hounsfield units for CT). Built once, read-only while rendering.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace multiray {

// Voxel types a volume file may hold (NRRD names: uchar, char, ushort, short, ...).
enum class VoxelType { u8, i8, u16, i16 };

// "uint8", "int8", "uint16", "int16": the names raw specs and messages use.
const char* voxel_type_name(VoxelType type);
// Bytes one voxel of `type` takes in a file: 1 or 2.
int voxel_bytes(VoxelType type);

struct Volume {
  std::string name;  // file name
  int nx = 0, ny = 0, nz = 0;
  Vec3 spacing{1, 1, 1};  // world units between voxel centres along x, y, z (> 0)
  VoxelType type = VoxelType::u8;
  std::vector<float> values;  // nx*ny*nz samples in the file's units, x fastest, then y, z
  float min_value = 0, max_value = 0;  // over all values

  size_t voxel_count() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  float at(int x, int y, int z) const {
    return values[(size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x)];
  }
  // World extent of the grid: voxel (i, j, k) has its centre at
  // lower() + ((i, j, k) + 0.5) * spacing; the box is centred on the origin.
  Vec3 extent() const { return Vec3{nx * spacing.x, ny * spacing.y, nz * spacing.z}; }
  Vec3 lower() const { return extent() * -0.5f; }
  Bounds3 bounds() const;
  // The shortest spacing: the "voxel length" step sizes are relative to.
  float voxel_length() const;
};

// Largest grid dimension and voxel count accepted from a file or the command line.
constexpr int kMaxVolumeDimension = 1 << 14;
constexpr size_t kMaxVolumeVoxels = size_t(1) << 31;

}  // namespace multiray
