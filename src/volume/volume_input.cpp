#include "volume/volume_input.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "core/scene_files.h"

namespace multiray::volume_detail {

using detail::fail;

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

void check_dimensions(const std::string& path, uint64_t nx, uint64_t ny, uint64_t nz) {
  const uint64_t n[3] = {nx, ny, nz};
  for (int a = 0; a < 3; ++a) {
    if (n[a] < 1 || n[a] > uint64_t(kMaxVolumeDimension))
      fail(path, "axis " + std::to_string(a) + " has " + std::to_string(n[a]) +
                     " samples; each axis must have 1.." + std::to_string(kMaxVolumeDimension));
  }
  // Each factor is at most 2^14, so the product fits in 64 bits.
  const uint64_t voxels = nx * ny * nz;
  if (voxels > kMaxVolumeVoxels)
    fail(path, std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + " is " +
                   std::to_string(voxels) + " voxels, more than the limit of " +
                   std::to_string(kMaxVolumeVoxels));
}

Vec3 checked_spacing(const std::string& path, const double s[3], const char* what) {
  Vec3 out;
  for (int a = 0; a < 3; ++a) {
    // Compared in double first: converting a double outside float's range is undefined.
    const bool ok = std::isfinite(s[a]) && s[a] >= kMinSpacing && s[a] <= kMaxSpacing;
    out[a] = ok ? float(s[a]) : 0.0f;
    if (!ok || !(out[a] >= kMinSpacing && out[a] <= kMaxSpacing))
      fail(path, std::string(what) + ": axis " + std::to_string(a) + " spacing " +
                     number_text(s[a]) + " is not a number in [1e-6, 1e6]");
  }
  const float lo = std::min(out.x, std::min(out.y, out.z));
  if (max_component(out) > kMaxSpacingRatio * lo)
    fail(path, std::string(what) + ": the longest spacing is more than " +
                   std::to_string(int(kMaxSpacingRatio)) + " times the shortest");
  return out;
}

uint64_t load_peak_bytes(uint64_t voxels, uint64_t file_bytes, uint64_t decoded_bytes) {
  return decoded_bytes + std::max(file_bytes, voxels * sizeof(float));
}

void check_memory(const std::string& path, const VolumeLoadOptions& options, uint64_t voxels,
                  uint64_t peak_bytes, const std::string& grid) {
  peak_bytes = std::max(peak_bytes, voxels * (sizeof(float) + options.kept_bytes_per_voxel));
  if (options.max_bytes != 0 && peak_bytes > options.max_bytes)
    fail(path, "loading " + grid + " needs about " + std::to_string(peak_bytes) +
                   " bytes, more than the limit of " + std::to_string(options.max_bytes));
}

uint64_t data_file_slack(uint64_t data_bytes) { return (uint64_t(1) << 20) + data_bytes / 256; }

void check_data_size(const std::string& path, const std::string& what, uint64_t have,
                     uint64_t need, const std::string& grid) {
  if (have == need) return;
  const uint64_t off = have < need ? need - have : have - need;
  fail(path, what + " is " + std::to_string(off) + (off == 1 ? " byte " : " bytes ") +
                 (have < need ? "short" : "too long") + ": it holds " + std::to_string(have) +
                 " bytes of voxel data, " + std::to_string(need) + " are needed for " + grid);
}

std::string grid_text(uint64_t nx, uint64_t ny, uint64_t nz, VoxelType type) {
  return std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + " " +
         voxel_type_name(type);
}

namespace {

// Voxel i of a packed array of T, its bytes reversed first when `swap`.
template <class T>
float voxel(const unsigned char* data, size_t i, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, data + i * sizeof(T), sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T t;
  std::memcpy(&t, b, sizeof(T));
  return float(t);
}

template <class T>
void convert(Volume* v, const unsigned char* data, bool swap) {
  using MinMax = std::pair<float, float>;
  const MinMax none{INFINITY, -INFINITY};
  const MinMax mm = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, v->values.size(), size_t(1) << 16), none,
      [&](const tbb::blocked_range<size_t>& r, MinMax m) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const float x = voxel<T>(data, i, swap);
          v->values[i] = x;
          m.first = std::min(m.first, x);
          m.second = std::max(m.second, x);
        }
        return m;
      },
      [](MinMax a, MinMax b) {
        return MinMax{std::min(a.first, b.first), std::max(a.second, b.second)};
      });
  v->min_value = mm.first;
  v->max_value = mm.second;
}

}  // namespace

void set_values(Volume* v, const void* data, bool swap_bytes) {
  v->values.assign(v->voxel_count(), 0.0f);
  const auto* bytes = static_cast<const unsigned char*>(data);
  switch (v->type) {
    case VoxelType::u8:
      convert<uint8_t>(v, bytes, false);
      break;
    case VoxelType::i8:
      convert<int8_t>(v, bytes, false);
      break;
    case VoxelType::u16:
      convert<uint16_t>(v, bytes, swap_bytes);
      break;
    case VoxelType::i16:
      convert<int16_t>(v, bytes, swap_bytes);
      break;
  }
}

}  // namespace multiray::volume_detail
