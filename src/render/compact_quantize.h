// Quantized vertex attributes of the compact scene (Seo, Park & Ihm, "Efficient Ray
// Tracing of Large 3D Scenes for Mobile Distributed Computing Environments", Sensors 22(2),
// 2022, §3): positions as a 16-bit index into a table of the grid's geometry cells plus
// three 10-bit offsets inside the cell (6 bytes instead of 12), unit normals in 16 bits (2
// instead of 12), texture coordinates as a per-triangle integer shift and 16 bits per
// component relative to it (4 bytes a vertex, and the shifts bit-packed per triangle,
// instead of 8 a vertex).
// Decoding (render/shared/compact.h, shared with the OpenCL kernel) is a table read and a
// few multiply-adds, done on access by the traversal and the shading of the device that
// chose the compact representation.
//
// Where we depart from the paper: normals use the octahedral map (Cigolle et al., "A
// survey of efficient representations for independent unit vectors", JCGT 2014) with 8
// bits per coordinate, an implicit table of 65,536 directions decoded arithmetically,
// instead of the paper's table of optimised spherical coordinates, so no table has to be
// stored on the device. The error bounds below are checked by tests/render/compact_test.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "render/compact_packed.h"
#include "render/shared/compact.h"

namespace multiray {

// At most this many geometry cells: the cell-index table is addressed by 16 bits.
inline constexpr uint32_t kMaxGridCells = 65536;
// At most this many cells along an axis: a cell coordinate is 16 bits in the table (the
// bisection stops one short, so that snapping the origin to the cell's last bit can add a
// cell).
inline constexpr uint32_t kMaxCellsPerAxis = 65536;
// Offsets inside a cell: 10 bits per axis, 0..1023 spanning the cell's full width.
inline constexpr uint32_t kOffsetLevels = 1023;

// The paper's position grid: cubic cells of side `cell` from `origin`, n[0] x n[1] x n[2]
// of them over the points' box, of which only the geometry cells (those holding one of the
// points) are listed in the cell-index table `cells`. The 2^16 limit applies to the table,
// not to the box, so a scene whose geometry fills little of its box gets a much finer grid
// than when every cell of the box counts (Sponza: about 16x finer per axis).
struct PositionGrid {
  Vec3 origin{0.0f};
  float cell = 1.0f;
  float step = 1.0f / float(kOffsetLevels);  // cell / 1023: one offset step
  uint32_t n[3] = {1, 1, 1};
  uint32_t divisions = 1;  // the bisection's N: cells along the longest side, before rounding
  // The cell-index table: x, y, z of each geometry cell, in z-y-x order; a vertex's 16-bit
  // cell index is an entry of it.
  std::vector<uint16_t> cells;

  // The finest grid whose geometry cells number at most kMaxGridCells: cell = longest
  // side / N rounded up to 8 significant bits, N found by bisection over
  // 1..kMaxCellsPerAxis - 1 with count_geometry_cells (N = 1 always fits: one cell). A point set
  // that is a single point gets one cell of side 1; an empty one the unit grid at the origin with
  // an empty table.
  // `max_cells` (at most kMaxGridCells) lowers the table's limit (geometry_cell_limit).
  static PositionGrid fit(const std::vector<Vec3>& points, uint32_t max_cells = kMaxGridCells);
  size_t cell_count() const { return cells.size() / 3; }
  size_t table_bytes() const { return cells.size() * sizeof(uint16_t); }
  // Largest distance, per axis, between a fitted point and its decoded position (half an
  // offset step; float rounding of the decoded sum comes on top).
  float max_error() const { return 0.5f * step; }
};

// The table's limit for a mesh of `vertices` vertices: the paper's 2^16, or one cell per 8
// vertices where that is fewer (ours; at least 1). The paper's rule, the finest grid whose
// geometry cells fit 2^16, was made for scenes of millions of vertices, where the table is
// full and every cell holds many vertices; below 2^19 vertices it gives each vertex a cell
// of its own, and the table (6 bytes a cell) then costs as much as the position codes it
// saves. With the cap a vertex costs at most 6 + 6/8 bytes instead of 12.
uint32_t geometry_cell_limit(size_t vertices);

// Geometry cells of `points` on the grid of `divisions` cells along the box's longest
// side (the bisection's measure), counted up to `limit` + 1: a result over `limit` means
// "more than limit".
uint32_t count_geometry_cells(const std::vector<Vec3>& points, uint32_t divisions,
                              uint32_t limit = kMaxGridCells);

// 6 bytes: index into the cell-index table and three 10-bit offsets packed into 30 of the
// 32 bits of `offsets_lo | offsets_hi << 16` (x in bits 0-9, y 10-19, z 20-29).
struct QuantizedPosition {
  uint16_t cell;
  uint16_t offsets_lo;
  uint16_t offsets_hi;
};
static_assert(sizeof(QuantizedPosition) == 6, "the paper's 6-byte vertex");

// `p` must be one of the points the grid was fitted to (its cell is listed); throws
// std::invalid_argument otherwise.
QuantizedPosition encode_position(const PositionGrid& grid, Vec3 p);

inline Vec3 decode_position(const PositionGrid& g, QuantizedPosition q) {
  return compact_decode_position(g.origin, g.cell, g.step, g.cells.data(), q.cell,
                                 uint32_t(q.offsets_lo) | uint32_t(q.offsets_hi) << 16);
}

// Octahedral code of a non-zero direction: 8 bits of u in the low byte, 8 of v in the high.
// The encoder picks the best of the four neighbouring codes (the "precise" variant), so
// the decoded direction is within kNormalErrorDegrees of the input.
uint16_t encode_normal(Vec3 n);
// Unit vector of a code (render/shared/compact.h, as the OpenCL kernel decodes it).
inline Vec3 decode_normal(uint16_t code) { return compact_decode_normal(code); }
// Bound on the angle between a unit vector and its decoded code, in degrees: the
// octahedral grid's covering radius at 8 bits per coordinate (0.86 degrees measured over
// dense sampling; the bound leaves a margin).
inline constexpr float kNormalErrorDegrees = 1.0f;

// Texture coordinates (the paper's per-triangle shift): each triangle stores an integer
// shift per component, the floor of its corners' smallest coordinate (textures that tile
// have coordinates like 37.25), and its corners' coordinates relative to the shift are
// quantized to 16 bits. The relative codes live once per vertex, as the coordinate modulo
// a period 2^period_log2 in steps of period / 65536 (one code serves every triangle of
// the vertex whatever its shift); the period is the smallest power of two, at least 1,
// that holds every triangle's relative coordinates, per component. Error at most step / 2
// per component plus the float rounding of shift + offset.
struct UvCoding {
  uint32_t period_log2[2] = {0, 0};
  float step[2] = {1.0f / 65536.0f, 1.0f / 65536.0f};
  float max_error(int axis) const { return 0.5f * step[axis]; }
};

// The triangles' integer shifts, packed (render/compact_packed.h): a triangle's entry holds
// its u shift's offset from base[0] in the low bits[0] bits and its v shift's offset from
// base[1] in the bits[1] bits above (ours; the paper stores a full integer per shift). A
// scene whose triangles all share one shift per component, as every scene with uvs in
// [0, 1] does, stores no entries at all.
struct UvShifts {
  int32_t base[2] = {0, 0};
  uint32_t bits[2] = {0, 0};
  PackedUints packed;  // one entry per triangle, bits[0] + bits[1] wide
  size_t bytes() const { return packed.bytes(); }
  int32_t shift(size_t tri, int axis) const {
    return compact_uv_shift(packed[tri], bits[0], base[axis], uint32_t(axis));
  }
};

// Quantized uvs of a mesh: `codes` two per vertex, `shifts` one entry per triangle.
struct QuantizedUvs {
  UvCoding coding;
  std::vector<uint16_t> codes;
  UvShifts shifts;
};
// `uvs` one per vertex, `indices` three per triangle. Shifts are clamped to the int16
// range (coordinates beyond +-32,767 lose the bound), periods to 2^15.
QuantizedUvs quantize_uvs(const std::vector<Vec2>& uvs, const std::vector<uint32_t>& indices);

// Corner `code` (two per vertex) of triangle `tri`.
inline Vec2 decode_uv(const UvCoding& c, const UvShifts& s, size_t tri, const uint16_t code[2]) {
  return Vec2{compact_decode_uv(s.shift(tri, 0), code[0], c.period_log2[0], c.step[0]),
              compact_decode_uv(s.shift(tri, 1), code[1], c.period_log2[1], c.step[1])};
}

}  // namespace multiray
