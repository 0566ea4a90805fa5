#include "render/voxel_grid.h"

#include <limits>

namespace multiray {

namespace {

// The values as T, or false when one of them is not exactly a T.
template <class T>
bool narrow_copy(const std::vector<float>& values, std::vector<uint8_t>& bytes) {
  bytes.resize(values.size() * sizeof(T));
  T* out = reinterpret_cast<T*>(bytes.data());
  for (size_t i = 0; i < values.size(); ++i) {
    const float f = values[i];
    // Range first: converting an out-of-range float to an integer is undefined.
    if (!(f >= float(std::numeric_limits<T>::min()) && f <= float(std::numeric_limits<T>::max())))
      return false;
    out[i] = T(f);
    if (float(out[i]) != f) return false;
  }
  return true;
}

}  // namespace

VoxelGrid make_voxel_grid(const Volume& v) {
  VoxelGrid g;
  bool ok = false;
  switch (v.type) {
    case VoxelType::u8:
      ok = narrow_copy<uint8_t>(v.values, g.bytes), g.store = VoxelGrid::Store::u8;
      break;
    case VoxelType::i8:
      ok = narrow_copy<int8_t>(v.values, g.bytes), g.store = VoxelGrid::Store::i8;
      break;
    case VoxelType::u16:
      ok = narrow_copy<uint16_t>(v.values, g.bytes), g.store = VoxelGrid::Store::u16;
      break;
    case VoxelType::i16:
      ok = narrow_copy<int16_t>(v.values, g.bytes), g.store = VoxelGrid::Store::i16;
      break;
  }
  if (!ok) {
    g.store = VoxelGrid::Store::f32;
    g.bytes.clear();
    g.bytes.shrink_to_fit();
  }
  return g;
}

}  // namespace multiray
