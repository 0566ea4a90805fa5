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

VolumeOrientation orientation_from_space(AnatomicalSpace space, Vec3 signs) {
  VolumeOrientation o;
  o.from_file = space != AnatomicalSpace::none;
  if (!o.from_file) space = kAssumedSpace, signs = Vec3{1, 1, 1};
  // In each space +x is left or right (no matter for the view), +z superior, and +y
  // anterior except in LPS.
  const Vec3 anterior{0, space == AnatomicalSpace::lps ? -1.0f : 1.0f, 0}, superior{0, 0, 1};
  for (int a = 0; a < 3; ++a) {
    const float s = signs[a] < 0 ? -1.0f : 1.0f;
    o.anterior[a] = anterior[a] * s;
    o.superior[a] = superior[a] * s;
  }
  return o;
}

}  // namespace multiray
