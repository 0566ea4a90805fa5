#include "volume/volume.h"

#include <algorithm>

namespace multiray {

const char* voxel_type_name(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "uint8";
    case VoxelType::i8:
      return "int8";
    case VoxelType::u16:
      return "uint16";
    case VoxelType::i16:
      return "int16";
  }
  return "unknown";
}

int voxel_bytes(VoxelType type) { return type == VoxelType::u8 || type == VoxelType::i8 ? 1 : 2; }

Bounds3 Volume::bounds() const {
  Bounds3 b;
  b.extend(lower());
  b.extend(lower() + extent());
  return b;
}

float Volume::voxel_length() const { return std::min(spacing.x, std::min(spacing.y, spacing.z)); }

}  // namespace multiray
