// Quantized vertex attributes of the compact scene (Seo, Park & Ihm, "Efficient Ray
// Tracing of Large 3D Scenes for Mobile Distributed Computing Environments", Sensors
// 22(2), 2022, §3): positions as a cell of a
// grid over the scene box plus three 10-bit offsets inside it (6 bytes instead of 12),
// unit normals in 16 bits (2 instead of 12), texture coordinates in 16 bits each (4
// instead of 8). Decoding is a few multiply-adds, done on access by the traversal and the
// shading of the device that chose the compact representation.
//
// Where we depart from the paper: normals use the octahedral map (Cigolle et al., "A
// survey of efficient representations for independent unit vectors", JCGT 2014) with 8
// bits per coordinate, an implicit table of 65,536 directions decoded arithmetically,
// instead of the paper's table of optimised spherical coordinates, so no table has to be
// stored on the device. The error bounds below are checked by tests/render/compact_test.cpp.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace multiray {

// At most this many cells cover the scene box (the 16-bit cell index of the paper).
inline constexpr uint32_t kMaxGridCells = 65536;
// Offsets inside a cell: 10 bits per axis, 0..1023 spanning the cell's full width.
inline constexpr uint32_t kOffsetLevels = 1023;

// x / d for x < 2^16 and 1 <= d <= 2^16 without a divide (a cell index is decoded at every
// triangle test, and an integer divide costs several multiplies): the high word of
// x * magic, magic = ceil(2^32 / d), is exactly floor(x / d) in that range, because with
// x = q d + r the excess x (magic - 2^32 / d) / 2^32 stays under 1 <= d - r. magic 0
// stands for d = 1. kernels/shading.cl decodes with the same numbers (mul_hi).
inline uint32_t division_magic(uint32_t d) {
  return d <= 1 ? 0 : uint32_t(((uint64_t(1) << 32) + d - 1) / d);
}
inline uint32_t divide_u16(uint32_t x, uint32_t magic) {
  return magic == 0 ? x : uint32_t((uint64_t(x) * magic) >> 32);
}

// Cubic cells of side `cell` from `origin`, n[0] x n[1] x n[2] of them (product at most
// kMaxGridCells), covering the box given to fit().
struct PositionGrid {
  Vec3 origin{0.0f};
  float cell = 1.0f;
  uint32_t n[3] = {1, 1, 1};
  // division_magic of n[0] and of n[0] * n[1], set with n by fit().
  uint32_t magic_n0 = 0, magic_n01 = 0;

  // The smallest cell size (found by bisection, as the paper does) for which whole cells
  // cover `box` within kMaxGridCells. A box that is a point or flat gets one cell along
  // each zero-length axis; an empty box gives the unit grid at the origin.
  static PositionGrid fit(const Bounds3& box);
  // Largest distance, per axis, between a point in the grid and its decoded position.
  float max_error() const { return cell / (2.0f * kOffsetLevels); }
};

// 6 bytes: cell index (x + n0 * (y + n1 * z)) and three 10-bit offsets packed into 30 of
// the 32 bits of `offsets_lo | offsets_hi << 16` (x in bits 0-9, y 10-19, z 20-29).
struct QuantizedPosition {
  uint16_t cell;
  uint16_t offsets_lo;
  uint16_t offsets_hi;
};
static_assert(sizeof(QuantizedPosition) == 6, "the paper's 6-byte vertex");

// `p` is clamped into the grid first (points outside it come back on its boundary).
QuantizedPosition encode_position(const PositionGrid& grid, Vec3 p);

inline Vec3 decode_position(const PositionGrid& g, QuantizedPosition q) {
  const uint32_t off = uint32_t(q.offsets_lo) | uint32_t(q.offsets_hi) << 16;
  const uint32_t cz = divide_u16(q.cell, g.magic_n01);
  const uint32_t rest = q.cell - cz * (g.n[0] * g.n[1]);
  const uint32_t cy = divide_u16(rest, g.magic_n0), cx = rest - cy * g.n[0];
  constexpr float k = 1.0f / float(kOffsetLevels);
  return Vec3(g.origin.x + g.cell * (float(cx) + float(off & 1023u) * k),
              g.origin.y + g.cell * (float(cy) + float((off >> 10) & 1023u) * k),
              g.origin.z + g.cell * (float(cz) + float((off >> 20) & 1023u) * k));
}

// Octahedral code of a non-zero direction: 8 bits of u in the low byte, 8 of v in the high.
// The encoder picks the best of the four neighbouring codes (the "precise" variant), so
// the decoded direction is within kNormalErrorDegrees of the input.
uint16_t encode_normal(Vec3 n);
// Unit vector of a code.
Vec3 decode_normal(uint16_t code);
// Bound on the angle between a unit vector and its decoded code, in degrees: the
// octahedral grid's covering radius at 8 bits per coordinate (0.86 degrees measured over
// dense sampling; the bound leaves a margin).
inline constexpr float kNormalErrorDegrees = 1.0f;

// Texture coordinates in 16 bits each, relative to the range of the scene's coordinates
// (which may exceed [0, 1] for repeating textures): error at most scale / 2 per component.
struct UvRange {
  Vec2 lo{0.0f, 0.0f};
  Vec2 scale{0.0f, 0.0f};  // (hi - lo) / 65535 per component
  static UvRange fit(Vec2 lo, Vec2 hi);
};
void encode_uv(const UvRange& r, Vec2 uv, uint16_t out[2]);
inline Vec2 decode_uv(const UvRange& r, const uint16_t q[2]) {
  return Vec2{r.lo.x + r.scale.x * float(q[0]), r.lo.y + r.scale.y * float(q[1])};
}

}  // namespace multiray
