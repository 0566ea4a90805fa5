// The compact scene (Seo, Park & Ihm 2022, §3): quantization error bounds, round trips,
// degenerate scenes, a traversal that finds exactly the hits of the decoded triangles,
// images within the PSNR bound of full precision, split independence and the `mem=` limit.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

#include "core/error.h"
#include "core/image_metrics.h"
#include "device/scene_memory.h"
#include "render/compact_accel.h"
#include "render/compact_scene.h"
#include "render/flat_bvh.h"
#include "render/shading_data.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace compact_test {

float angle_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.0f, 1.0f)) * 57.29578f;
}

// Points spread uniformly over a box (dense: every cell of a fine grid is occupied).
std::vector<Vec3> points_in(const Bounds3& b, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.push_back(b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent());
  return points;
}

// Every point decodes within half an offset step of its cell, per axis, plus the rounding
// of the decoded sum at the point's own magnitude (the corner is exact: lattice()).
void expect_within_half_a_step(const PositionGrid& g, const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    const Vec3 d = decode_position(g, encode_position(g, p));
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(std::fabs(d[a] - p[a]), g.max_error() + 1.2e-7f * (std::fabs(p[a]) + g.cell))
          << a << ": " << p[a] << " -> " << d[a];
  }
}

TEST(CompactQuantize, PositionErrorIsHalfAnOffsetStepOfTheGrid) {
  const Bounds3 boxes[] = {{{-1, -1, -1}, {1, 1, 1}},
                           {{0, 0, 0}, {1000, 3, 0.01f}},
                           {{-1e4f, 5, 5}, {1e4f, 5.5f, 9}},
                           {{3, 3, 3}, {3, 3, 4}}};  // flat in x and y
  uint32_t seed = 7;
  for (const Bounds3& b : boxes) {
    const std::vector<Vec3> points = points_in(b, 100000, seed++);
    const PositionGrid g = PositionGrid::fit(points);
    ASSERT_LE(g.cell_count(), kMaxGridCells);
    Bounds3 box;
    for (const Vec3& p : points) box.extend(p);
    for (int a = 0; a < 3; ++a) {  // the grid covers the points
      EXPECT_LE(g.origin[a], box.lo[a]);
      EXPECT_GE(double(g.origin[a]) + double(g.n[a]) * g.cell, double(box.hi[a]));
    }
    expect_within_half_a_step(g, points);
  }
}

// The geometry-cell table (Seo et al. §3): it lists exactly the cells that hold a vertex,
// each once, at most 2^16 of them, in the table's z-y-x order; every vertex's index
// points at the cell that contains it.
TEST(CompactQuantize, CellTableListsOnlyTheGeometryCells) {
  const Scene scene = make_lit_sphere(0.8f, 200, 400, true);  // 80,000 vertices
  const PositionGrid g = PositionGrid::fit(scene.positions);
  ASSERT_EQ(g.cells.size() % 3, 0u);
  ASSERT_LE(g.cell_count(), kMaxGridCells);
  std::vector<int> used(g.cell_count(), 0);
  for (const Vec3& p : scene.positions) {
    const QuantizedPosition q = encode_position(g, p);
    ASSERT_LT(q.cell, g.cell_count());
    ++used[q.cell];
    for (int a = 0; a < 3; ++a) {  // the listed cell contains the point
      const double lo = double(g.origin[a]) + double(g.cells[3 * q.cell + a]) * g.cell;
      EXPECT_GE(double(p[a]), lo - 1e-6) << a;
      EXPECT_LE(double(p[a]), lo + g.cell + 1e-6) << a;
      EXPECT_LT(g.cells[3 * q.cell + a], g.n[a]);
    }
  }
  const auto key = [&](size_t i) {
    return uint64_t(g.cells[3 * i + 2]) << 32 | uint64_t(g.cells[3 * i + 1]) << 16 |
           g.cells[3 * i];
  };
  for (size_t i = 0; i < g.cell_count(); ++i) {
    EXPECT_GT(used[i], 0) << "an empty cell is listed: " << i;
    if (i > 0) {
      EXPECT_LT(key(i - 1), key(i)) << "not sorted, or listed twice: " << i;
    }
  }
  // The sphere's surface fills a small share of its box's cells.
  EXPECT_LT(double(g.cell_count()), 0.2 * double(g.n[0]) * g.n[1] * g.n[2]);
}

// The bisection: the chosen resolution fits and the next finer one does not (a sphere of
// 80,000 vertices needs more than 2^16 cells at the finest resolution).
TEST(CompactQuantize, GridIsTheFinestWhoseGeometryCellsFit) {
  const Scene scene = make_lit_sphere(0.8f, 200, 400, true);
  const PositionGrid g = PositionGrid::fit(scene.positions);
  const uint32_t divisions = g.divisions;
  ASSERT_GT(divisions, 1u);
  ASSERT_LT(divisions, kMaxCellsPerAxis);
  EXPECT_EQ(count_geometry_cells(scene.positions, divisions), g.cell_count());
  EXPECT_GT(count_geometry_cells(scene.positions, divisions + 1), kMaxGridCells);
  EXPECT_GT(g.cell_count(), kMaxGridCells / 2);  // the table is well used
  // A few vertices: every one may have a cell of its own, at the finest resolution.
  const std::vector<Vec3> few = {{0, 0, 0}, {1, 2, 3}, {-5, 0.5f, 2}};
  const PositionGrid fine = PositionGrid::fit(few);
  EXPECT_EQ(fine.cell_count(), 3u);
  EXPECT_GE(fine.cell, 6.0f / float(kMaxCellsPerAxis - 1));
  EXPECT_LE(fine.cell, 6.0f / float(kMaxCellsPerAxis - 1) * (1.0f + 1.0f / 128));
}

// A mesh of few vertices (ours, geometry_cell_limit): the paper's rule alone would give
// nearly every vertex a cell of its own, a table as big as the position codes; the compact
// mesh keeps at most one cell per 8 vertices, and its vertices still decode within half a
// step of its grid.
TEST(CompactQuantize, SmallMeshesKeepTheTableSmall) {
  const Scene scene = make_lit_sphere(0.8f, 60, 120, true);
  const size_t vertices = scene.positions.size();  // 28,806, of 7,086 distinct positions
  std::set<std::tuple<float, float, float>> distinct;
  for (const Vec3& p : scene.positions) distinct.insert({p.x, p.y, p.z});
  EXPECT_GT(PositionGrid::fit(scene.positions).cell_count(), distinct.size() * 9 / 10);
  const CompactMesh m = build_compact_mesh(scene);
  EXPECT_LE(m.grid.cell_count(), geometry_cell_limit(vertices));
  EXPECT_LE(m.grid.table_bytes() * 8, vertices * 6);
  expect_within_half_a_step(m.grid, scene.positions);
  EXPECT_EQ(geometry_cell_limit(size_t(1) << 20), kMaxGridCells);  // the paper's scenes
  EXPECT_EQ(geometry_cell_limit(3), 1u);
}

// Whole-box counting (every cell of the box within 2^16): the smallest cubic cell for a
// box of extent `e`, as the encoding before the cell table chose it (a lower bound).
double whole_box_cell(Vec3 e) { return std::cbrt(double(e.x) * e.y * e.z / kMaxGridCells); }

// A ball with a small quad 1,000 units away: counting the whole box gives cells of ~25
// units, as large as the ball; counting geometry cells gives a grid ~20 times finer per
// axis (the 16-bit cell coordinates stop it there: 65,535 cells along 1,000 units), and
// the ball's vertices decode within half a step of that grid.
TEST(CompactQuantize, SpreadSceneGetsAFinerGridThanTheWholeBoxRule) {
  Scene scene = make_lit_sphere(1.0f, 48, 96, true);
  for (const Vec3& p : {Vec3(-1000, -1000, -1000), Vec3(-1000, -999, -1000),
                        Vec3(-999, -999, -1000), Vec3(-999, -1000, -1000)})
    scene.positions.push_back(p);
  const PositionGrid g = PositionGrid::fit(scene.positions);
  const double whole_box = whole_box_cell(scene.bounds().extent());
  std::printf("cell %.4g (whole-box rule: at least %.4g), %zu geometry cells\n", g.cell, whole_box,
              g.cell_count());
  EXPECT_LT(g.cell, whole_box / 10);
  expect_within_half_a_step(g, scene.positions);
  // So the worst error near the ball is far under what the whole-box grid could promise.
  float worst = 0;
  for (const Vec3& p : scene.positions) {
    if (length(p) > 100) continue;  // the far quad: float rounding at 1,000 dominates
    const Vec3 d = decode_position(g, encode_position(g, p));
    worst = std::max({worst, std::fabs(d.x - p.x), std::fabs(d.y - p.y), std::fabs(d.z - p.z)});
  }
  EXPECT_LT(worst, whole_box / 2046 / 10);
}

TEST(CompactQuantize, EncodingAPointOutsideTheTableIsRefused) {
  const PositionGrid g = PositionGrid::fit({{0, 0, 0}, {10, 10, 10}});
  EXPECT_THROW(encode_position(g, Vec3(5, 5, 5)), std::invalid_argument);
}

TEST(CompactQuantize, PositionCodesRoundTrip) {
  const PositionGrid g = PositionGrid::fit(points_in(Bounds3{{-2, 0, 1}, {5, 1, 3}}, 50000, 3));
  std::mt19937 rng(3);
  for (int i = 0; i < 20000; ++i) {
    const uint32_t cell = rng() % g.cell_count();
    // Offsets short of the far side: 1023 is the next cell's corner, maybe unlisted, and
    // this grid's step (1e-7) is under a float's spacing at 3, so the decoded point may
    // round a step or two across.
    const uint32_t off = rng() % 1000 | (rng() % 1000) << 10 | (rng() % 1000) << 20;
    const QuantizedPosition q{uint16_t(cell), uint16_t(off & 0xffff), uint16_t(off >> 16)};
    const Vec3 p = decode_position(g, q);
    const Vec3 again = decode_position(g, encode_position(g, p));
    EXPECT_LE(length(again - p), 1e-5f);
  }
}

TEST(CompactQuantize, NormalErrorIsUnderTheTablesBound) {
  std::mt19937 rng(11);
  std::normal_distribution<float> n(0, 1);
  float worst = 0;
  for (int i = 0; i < 300000; ++i) {
    const Vec3 v(n(rng), n(rng), n(rng));
    if (length(v) < 1e-3f) continue;
    worst = std::max(worst, angle_deg(v, decode_normal(encode_normal(v))));
  }
  for (const Vec3 v : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(1, 1, 1),
                       Vec3(-1, 1e-7f, -1), Vec3(0, 1e-9f, -1)})
    worst = std::max(worst, angle_deg(v, decode_normal(encode_normal(v))));
  EXPECT_LT(worst, kNormalErrorDegrees);
  EXPECT_GT(worst, 0.1f);  // 8 bits per coordinate cannot be exact
}

// Codes of the upper hemisphere come back exactly. Below it the octahedral fold does not
// map the lattice onto itself, so a code may come back as a neighbour, within the bound,
// and after one trip the code is stable.
TEST(CompactQuantize, EveryNormalCodeDecodesToAUnitVectorThatEncodesBack) {
  for (uint32_t c = 0; c < 65536; ++c) {
    const Vec3 d = decode_normal(uint16_t(c));
    ASSERT_NEAR(length(d), 1.0f, 1e-5f) << c;
    const uint16_t again = encode_normal(d);
    if (d.z > 1e-3f) {
      EXPECT_EQ(again, c) << c;
    }
    EXPECT_LT(angle_deg(decode_normal(again), d), kNormalErrorDegrees) << c;
    EXPECT_EQ(encode_normal(decode_normal(again)), again) << c;
  }
}

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

Vec2 decoded_uv(const QuantizedUvs& q, const std::vector<uint32_t>& indices, size_t tri, int k) {
  return decode_uv(q.coding, q.shifts, tri, &q.codes[2 * indices[3 * tri + k]]);
}

// Triangles spanning less than one texture repeat each, anywhere in [-100, 100]: after the
// per-triangle shift they need a period of 2 at most, so each corner is within half a step
// of 2 / 65536 (plus the rounding of shift + offset), however wide the scene's range.
TEST(CompactQuantize, UvErrorPerTriangleIsHalfAStepAfterTheShift) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec2> uvs;
  std::vector<uint32_t> indices;
  for (int t = 0; t < 5000; ++t) {
    const Vec2 base{-100 + 200 * u(rng), -100 + 200 * u(rng)};
    for (int k = 0; k < 3; ++k) {
      indices.push_back(uint32_t(uvs.size()));
      uvs.push_back(Vec2{base.x + 0.9f * u(rng), base.y + 0.9f * u(rng)});
    }
  }
  const QuantizedUvs q = quantize_uvs(uvs, indices);
  for (int a = 0; a < 2; ++a) EXPECT_LE(q.coding.period_log2[a], 1u);
  for (size_t t = 0; t < indices.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec2 want = uvs[indices[3 * t + k]], got = decoded_uv(q, indices, t, k);
      ASSERT_LE(std::fabs(got.x - want.x), q.coding.max_error(0) + 4e-6f) << t;
      ASSERT_LE(std::fabs(got.y - want.y), q.coding.max_error(1) + 4e-6f) << t;
      EXPECT_LE(q.coding.max_error(0), 1.0f / 65536.0f);
    }
}

// Tiling coordinates (a texture repeated 37 times) decode exactly where they are
// representable in the step after the shift, beside a triangle at the origin; a vertex shared by
// two triangles with different shifts decodes right in both.
TEST(CompactQuantize, TilingUvsDecodeRight) {
  // 37.75 + 2^-15: a step of the period 2 after the shift, under the step of a range
  // reaching from 0 (or -3) to 38.5.
  const std::vector<Vec2> uvs = {{37.25f, 0.5f}, {37.75f + 1.0f / 32768, 0.5f},
                                 {37.5f, 1.0f},  {0.0f, -3.0f},
                                 {1.0f, -3.0f},  {0.5f, -2.25f},
                                 {38.5f, 1.5f}};
  const std::vector<uint32_t> indices = {0, 1, 2, 3, 4, 5, 1, 6, 2};
  const QuantizedUvs q = quantize_uvs(uvs, indices);
  EXPECT_EQ(q.shifts.shift(0, 0), 37);
  EXPECT_EQ(q.shifts.shift(0, 1), 0);
  EXPECT_EQ(q.shifts.shift(1, 1), -3);
  for (size_t t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec2 want = uvs[indices[3 * t + k]], got = decoded_uv(q, indices, t, k);
      EXPECT_EQ(got.x, want.x) << t << " " << k;
      EXPECT_EQ(got.y, want.y) << t << " " << k;
    }
}

// Bit packing (render/compact_packed.h): values of every width from 0 to 32 bits come back
// from compact_read_bits (the kernel's reader), across word boundaries, and the array
// takes ceil(count x width / 32) words.
TEST(CompactPacked, ValuesOfEveryWidthRoundTrip) {
  std::mt19937 rng(17);
  for (uint32_t width = 0; width <= 32; ++width) {
    std::vector<uint32_t> values(1001);
    for (uint32_t& v : values) v = width == 32 ? rng() : (rng() & ((1u << width) - 1u));
    if (width > 0) values[7] = width == 32 ? ~0u : (1u << width) - 1u;  // the largest
    const PackedUints p = PackedUints::pack(values);
    EXPECT_EQ(p.width, width);
    EXPECT_EQ(p.bytes(), (values.size() * width + 31) / 32 * 4) << width;
    for (size_t i = 0; i < values.size(); ++i)
      ASSERT_EQ(compact_read_bits(p.words.data(), i, width), values[i]) << width << " " << i;
  }
  EXPECT_EQ(bits_for(0), 0u);
  EXPECT_EQ(bits_for(1), 1u);
  EXPECT_EQ(bits_for(65535), 16u);
  EXPECT_EQ(bits_for(65536), 17u);
  EXPECT_EQ(bits_for(~0u), 32u);
}

// The faces take the bits of the largest vertex index and the material ids those of the
// largest id (none for one material), and decode to the scene's.
TEST(CompactScene, FacesAndMaterialsTakeTheBitsOfTheirLargestValue) {
  for (const Scene& scene : {make_cornell_box(), make_lit_sphere(0.8f, 48, 96, true)}) {
    const CompactMesh m = build_compact_mesh(scene);
    const size_t tris = scene.triangle_count();
    ASSERT_EQ(m.triangle_count(), tris);
    uint32_t largest_material = 0;
    for (uint32_t id : scene.material_ids) largest_material = std::max(largest_material, id);
    const uint32_t index_bits = bits_for(uint32_t(m.positions.size() - 1));
    const CompactMesh::Parts parts = m.parts();
    EXPECT_EQ(parts.faces, (3 * tris * index_bits + 31) / 32 * 4) << scene.name;
    EXPECT_EQ(parts.materials, (tris * bits_for(largest_material) + 31) / 32 * 4) << scene.name;
    EXPECT_GE(estimate_compact_bytes(scene).mesh, m.bytes()) << scene.name;
    for (uint32_t t = 0; t < tris; ++t) {
      ASSERT_EQ(m.material(t), scene.material_ids[t]) << scene.name << " " << t;
      for (int k = 0; k < 3; ++k)
        ASSERT_TRUE(
            same(m.corner(t, k),
                 decode_position(
                     m.grid, encode_position(m.grid, scene.positions[scene.indices[3 * t + k]]))))
            << scene.name << " " << t;
    }
  }
  Scene one_material = make_lit_sphere(0.8f, 48, 96, true);
  std::fill(one_material.material_ids.begin(), one_material.material_ids.end(), 0u);
  EXPECT_EQ(build_compact_mesh(one_material).parts().materials, 0u);
}

// Every corner its own vertex, as an OBJ loader makes them.
Scene unindexed(const Scene& s) {
  Scene out = s;
  out.positions.clear(), out.normals.clear(), out.uvs.clear(), out.indices.clear();
  for (uint32_t i : s.indices) {
    out.indices.push_back(uint32_t(out.positions.size()));
    out.positions.push_back(s.positions[i]);
    if (!s.normals.empty()) out.normals.push_back(s.normals[i]);
    if (!s.uvs.empty()) out.uvs.push_back(s.uvs[i]);
  }
  return out;
}

// The tree's triangle references take the bits of the largest triangle index, and every
// triangle with an area is referenced from the leaves.
TEST(CompactScene, TreeReferencesTakeTheBitsOfTheLargestTriangle) {
  const Scene scene = make_lit_sphere(0.8f, 48, 96, true);
  const CompactScene c = build_compact_scene(scene);
  const uint32_t bits = bits_for(uint32_t(scene.triangle_count() - 1));
  EXPECT_EQ(c.bvh.prims.width, bits);
  EXPECT_EQ(c.bvh.bytes(),
            c.bvh.nodes.size() * sizeof(CompactNode) + (c.bvh.prims.size() * bits + 31) / 32 * 4);
  std::vector<int> seen(scene.triangle_count(), 0);
  for (uint32_t p : c.bvh.prims.unpacked()) {
    ASSERT_LT(p, scene.triangle_count());
    ++seen[p];
  }
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    if (seen[t] > 0) continue;  // only triangles without area (the sphere's poles) are left out
    const Vec3 a = c.mesh.corner(t, 0);
    const Vec3 n = cross(c.mesh.corner(t, 1) - a, c.mesh.corner(t, 2) - a);
    EXPECT_EQ(length(n), 0.0f) << t;
  }
  EXPECT_GE(estimate_compact_bytes(scene).structure, c.bvh.bytes());
}

// Vertices duplicated with the same position, normal and uv are stored once: the
// unindexed sphere's compact mesh has as many vertices as distinct (position, normal, uv),
// and every corner, normal and uv decodes exactly as the unwelded vertices' codes would
// (same grid, same uv coding).
TEST(CompactScene, DuplicatedVerticesAreWelded) {
  Scene indexed = make_lit_sphere(0.8f, 48, 96, true);
  ASSERT_FALSE(indexed.normals.empty());
  indexed.uvs.clear();  // tiling uvs, from the positions
  for (const Vec3& p : indexed.positions) indexed.uvs.push_back(Vec2{3 * p.x, 2 * p.y + p.z});
  const Scene s = unindexed(indexed);
  std::set<std::array<uint32_t, 8>> distinct;  // bit patterns: -0 is not +0
  const auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
  for (size_t v = 0; v < s.positions.size(); ++v) {
    const Vec3 p = s.positions[v], n = s.normals[v];
    const Vec2 uv = s.uvs[v];
    distinct.insert({bits(p.x), bits(p.y), bits(p.z), bits(n.x), bits(n.y), bits(n.z), bits(uv.x),
                     bits(uv.y)});
  }
  const CompactMesh m = build_compact_mesh(s);
  EXPECT_EQ(m.positions.size(), distinct.size());
  EXPECT_LT(3 * m.positions.size(), s.positions.size());
  const PositionGrid grid =
      PositionGrid::fit(s.positions, geometry_cell_limit(s.positions.size()));
  EXPECT_EQ(m.grid.cells, grid.cells);
  EXPECT_GE(estimate_compact_bytes(s).mesh, m.bytes());  // the `mem=` check's upper bound
  const QuantizedUvs uvs = quantize_uvs(s.uvs, s.indices);
  for (uint32_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = s.indices[3 * t + k];
      ASSERT_TRUE(
          same(m.corner(t, k), decode_position(grid, encode_position(grid, s.positions[v]))))
          << t;
      ASSERT_EQ(m.normals[m.vertex(t, k)], encode_normal(s.normals[v])) << t;
      const Vec2 want = decoded_uv(uvs, s.indices, t, k), got = m.uv(t, k);
      ASSERT_EQ(got.x, want.x) << t;
      ASSERT_EQ(got.y, want.y) << t;
    }
}

// The uv shifts are packed relative to the smallest shift per component: uvs within one
// repeat need no shifts stored at all, tiling uvs as many bits as their shifts' range,
// and both decode within the bound of the period's step.
TEST(CompactQuantize, UvShiftsTakeTheBitsOfTheirRange) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec2> uvs;
  std::vector<uint32_t> indices;
  for (int t = 0; t < 3000; ++t)
    for (int k = 0; k < 3; ++k) {
      indices.push_back(uint32_t(uvs.size()));
      uvs.push_back(Vec2{0.999f * u(rng), 0.999f * u(rng)});
    }
  const QuantizedUvs unit = quantize_uvs(uvs, indices);
  EXPECT_EQ(unit.shifts.bytes(), 0u);
  // Shift each triangle by an integer in [-3, 37] in u and [5, 6] in v.
  for (size_t t = 0; t < indices.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) {
      Vec2& uv = uvs[indices[3 * t + k]];
      uv.x += float(int(t % 41) - 3), uv.y += float(5 + t % 2);
    }
  const QuantizedUvs tiled = quantize_uvs(uvs, indices);
  EXPECT_EQ(tiled.shifts.base[0], -3);
  EXPECT_EQ(tiled.shifts.base[1], 5);
  EXPECT_EQ(tiled.shifts.bits[0], 6u);
  EXPECT_EQ(tiled.shifts.bits[1], 1u);
  EXPECT_EQ(tiled.shifts.bytes(), (3000 * 7 + 31) / 32 * 4);
  for (size_t t = 0; t < indices.size() / 3; ++t) {
    EXPECT_EQ(tiled.shifts.shift(t, 0), int(t % 41) - 3);
    for (int k = 0; k < 3; ++k) {
      const Vec2 want = uvs[indices[3 * t + k]], got = decoded_uv(tiled, indices, t, k);
      ASSERT_LE(std::fabs(got.x - want.x), tiled.coding.max_error(0) + 4e-6f) << t;
      ASSERT_LE(std::fabs(got.y - want.y), tiled.coding.max_error(1) + 4e-6f) << t;
    }
  }
}

// A sphere of many small triangles, with normals and uvs.
Scene sphere_scene() { return make_lit_sphere(0.8f, 48, 96, true); }

// Rays from around the scene towards points near random vertices of it.
std::vector<Ray> random_rays(const Scene& s, int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  const Bounds3 b = s.bounds();
  const float r = length(b.extent());
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    const Vec3 jitter = Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * (0.02f * r);
    const Vec3 target = s.positions[rng() % s.positions.size()] + jitter;
    const Vec3 org = b.center() + normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f)) * r;
    rays.push_back(Ray{org, normalize(target - org), 0.0f, INFINITY});
  }
  return rays;
}

// The quantized tree must be conservative: every hit Embree finds on the decoded
// triangles, the compact traversal finds too, at the same distance on the same triangle.
TEST(CompactTraversal, FindsTheHitsOfTheDecodedTriangles) {
  for (const Scene& scene : {make_cornell_box(), sphere_scene()}) {
    const CompactScene c = build_compact_scene(scene);
    Scene decoded = scene;  // the compact mesh's vertices are welded: set them by corner
    for (uint32_t t = 0; t < scene.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k)
        decoded.positions[scene.indices[3 * t + k]] = c.mesh.corner(t, k);
    const Accel embree(decoded);
    int hits = 0, same = 0, missed = 0, other = 0;
    for (const Ray& ray : random_rays(scene, 20000)) {
      Hit a, b;
      const bool ha = embree.intersect(ray, a), hb = compact_intersect(c, nullptr, ray, b);
      EXPECT_EQ(compact_occluded(c, nullptr, ray), hb);
      if (!ha) continue;
      ++hits;
      missed += !hb;
      other += hb && b.prim != a.prim;
      // Another triangle at the same distance is a tie (the Cornell box has coplanar
      // quads, and a ray through a shared edge may take either side).
      same += hb && std::fabs(b.t - a.t) <= 1e-4f * a.t;
    }
    std::printf("%s: %d hits, %d missed, %d on another triangle\n", scene.name.c_str(), hits,
                missed, other);
    ASSERT_GT(hits, 5000);
    // Embree's watertight test and our Moller-Trumbore may split a ray on a shared edge
    // differently: allow that, nothing more.
    EXPECT_GE(same, hits - hits / 500) << scene.name << ": " << same << " of " << hits;
  }
}

// The same tree decoded once into floats (the full-precision side of the paper's
// comparison, bench/compact_bench.cpp) finds exactly the compact traversal's hits: the
// same triangle, distance, barycentrics and normal, bit for bit, ray for ray.
TEST(CompactTraversal, TheFloatTwinFindsTheSameHitsBitForBit) {
  for (const Scene& scene : {make_cornell_box(), sphere_scene()}) {
    const CompactScene c = build_compact_scene(scene);
    const CompactFloatTree twin = decode_compact_tree(c);
    ASSERT_EQ(twin.nodes.size(), c.bvh.nodes.size());
    ASSERT_EQ(twin.triangles.size(), 3 * c.bvh.prims.size());
    ASSERT_EQ(twin.faces.size(), 3 * size_t(scene.triangle_count()));
    int hits = 0;
    for (const Ray& ray : random_rays(scene, 20000)) {
      Hit a, b;
      const bool ha = compact_intersect(c, nullptr, ray, a);
      for (bool per_slot : {false, true}) {
        ASSERT_EQ(compact_float_intersect(twin, c, nullptr, ray, b, per_slot), ha);
        if (!ha) continue;
        ASSERT_EQ(std::memcmp(&a.t, &b.t, sizeof(float)), 0);
        ASSERT_EQ(a.prim, b.prim);
        ASSERT_EQ(std::memcmp(&a.u, &b.u, sizeof(float)), 0);
        ASSERT_EQ(std::memcmp(&a.v, &b.v, sizeof(float)), 0);
        ASSERT_EQ(std::memcmp(&a.ng, &b.ng, sizeof(Vec3)), 0);
      }
      if (!ha) continue;
      ++hits;
    }
    EXPECT_GT(hits, 5000) << scene.name;
  }
}

// Every decoded box of the compact tree (render/shared/compact.h's arithmetic, as the
// traversal decodes it) holds every decoded triangle below it, to the last bit: the boxes
// are conservative by construction, not by a tolerance. Triangles far from the origin
// and of awkward sizes, where the planes' rounding matters most.
void expect_boxes_hold_triangles(const CompactScene& c, const CompactFloatTree& t, uint32_t node,
                                 std::vector<std::array<float, 6>>& path) {
  for (int k = 0; k < 2; ++k) {
    const auto& p = t.nodes[node].planes;  // x, y, z rows: c0 lo, c1 lo, c0 hi, c1 hi
    path.push_back({p[k], p[4 + k], p[8 + k], p[2 + k], p[6 + k], p[10 + k]});
    const uint32_t ref = t.nodes[node].child[k];
    if (!(ref & kLeafBit)) {
      expect_boxes_hold_triangles(c, t, ref, path);
    } else {
      const uint32_t first = (ref & ~kLeafBit) >> kLeafCountBits;
      for (uint32_t i = first; i <= first + (ref & (kMaxLeafTriangles - 1)); ++i)
        for (int v = 0; v < 3; ++v) {
          const Vec3 q = c.mesh.corner(t.prims[i], v);
          for (const auto& b : path)
            for (int a = 0; a < 3; ++a)
              ASSERT_TRUE(b[a] <= q[a] && q[a] <= b[3 + a])
                  << "axis " << a << ": " << q[a] << " outside [" << b[a] << ", " << b[3 + a]
                  << "]";
        }
    }
    path.pop_back();
  }
}

// A plane's code is safe and tight, at random and at the values where rounding bites: on
// a decoded plane and an ulp either side of it.
TEST(CompactScene, EveryPlaneCodeIsSafeAndTight) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 20000; ++i) {
    const float lo = (u(rng) - 0.5f) * std::pow(10.0f, float(rng() % 9) - 3.0f);
    const float hi = lo + u(rng) * std::pow(10.0f, float(rng() % 7) - 3.0f);
    if (!(hi > lo)) continue;
    const uint8_t k = uint8_t(rng() % 256);
    for (bool upper : {false, true}) {
      const float on = compact_dequantize_plane(lo, hi, k, !upper);  // the other side's plane
      for (float value : {lo + (hi - lo) * u(rng), on, std::nextafter(on, -INFINITY),
                          std::nextafter(on, INFINITY)}) {
        if (!(value >= lo && value <= hi)) continue;
        const uint8_t q = quantize_plane(lo, hi, value, upper);
        const float d = compact_dequantize_plane(lo, hi, q, upper);
        ASSERT_TRUE(upper ? d >= value : d <= value)
            << (upper ? "upper" : "lower") << " " << lo << ".." << hi << " value " << value;
        // Tight: within a code's width of `value` (two, for the rounding of q / 255), plus
        // a few ulps where a code is narrower than the floats around it.
        const float ulp = std::nextafter(std::fabs(value), INFINITY) - std::fabs(value);
        ASSERT_LE(std::fabs(d - value), 2.0f * (hi - lo) / 255.0f + 4.0f * ulp)
            << (upper ? "upper" : "lower") << " code " << int(q) << " too loose";
      }
    }
  }
}

TEST(CompactScene, EveryDecodedBoxHoldsEveryTriangleBelowIt) {
  Scene soup = make_cornell_box();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  soup.positions.clear(), soup.normals.clear(), soup.uvs.clear(), soup.indices.clear();
  for (uint32_t i = 0; i < 30000; ++i) {
    const Vec3 centre(1000.0f + 37.0f * u(rng), -5000.0f + 3.0f * u(rng), 0.1f * u(rng));
    for (int v = 0; v < 3; ++v) {
      soup.positions.push_back(centre + Vec3(u(rng), u(rng), u(rng)) * (0.3f * u(rng)));
      soup.indices.push_back(uint32_t(soup.positions.size() - 1));
    }
  }
  soup.material_ids.assign(soup.indices.size() / 3, 0);
  for (const Scene& scene : {sphere_scene(), soup}) {
    const CompactScene c = build_compact_scene(scene);
    const CompactFloatTree t = decode_compact_tree(c);
    ASSERT_FALSE(t.nodes.empty());
    std::vector<std::array<float, 6>> path;
    expect_boxes_hold_triangles(c, t, 0, path);
  }
}

Scene one_triangle(Vec3 a, Vec3 b, Vec3 c) {
  Scene s = make_cornell_box();
  s.positions = {a, b, c};
  s.normals.clear(), s.uvs.clear();
  s.indices = {0, 1, 2};
  s.material_ids = {0};
  s.environment = Vec3(0.5f);
  return s;
}

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// All vertices equal: nothing can be hit, as at full precision (the same image).
TEST(CompactScene, DegenerateScenesRender) {
  const RenderSettings settings{.spp = 2, .max_bounces = 3};
  const Scene point = one_triangle(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1));
  EXPECT_TRUE(build_compact_scene(point).bvh.nodes.empty());
  EXPECT_TRUE(identical(
      testing::render_regions(point, 16, 16, settings, {{0, 0, 16, 16}}),
      testing::render_regions(point, 16, 16, settings, {{0, 0, 16, 16}}, 1, 1, 0, true)));
  // A flat scene and a single triangle: rendered, and close to full precision.
  Scene tri = one_triangle(Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0));
  tri.cameras = {Camera{{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 60}};
  const Framebuffer full = testing::render_regions(tri, 32, 32, settings, {{0, 0, 32, 32}});
  const Framebuffer small =
      testing::render_regions(tri, 32, 32, settings, {{0, 0, 32, 32}}, 1, 1, 0, true);
  EXPECT_GE(image_error(small, full).psnr_db, 40.0);
}

// The bound: PSNR >= 40 dB against the full-precision render with the same seeds.
// Paths use the same random numbers in both, but a path that meets an edge or a Russian
// roulette threshold differently continues elsewhere: that part of the difference is
// Monte Carlo noise and falls with the sample count (Cornell box: 32 dB at 8 spp, 40.3 at
// 64), so the images are compared at 128 spp.
TEST(CompactScene, ImagesAreWithinThePsnrBoundOfFullPrecision) {
  const RenderSettings settings{.spp = 128, .max_bounces = 4};
  for (const Scene& scene : {make_cornell_box(), sphere_scene()}) {
    const Framebuffer full = testing::render_regions(scene, 64, 48, settings, {{0, 0, 64, 48}});
    const Framebuffer small =
        testing::render_regions(scene, 64, 48, settings, {{0, 0, 64, 48}}, 1, 1, 0, true);
    EXPECT_FALSE(identical(full, small)) << scene.name;  // it is a different representation
    const ImageError e = image_error(small, full);
    std::printf("%s: PSNR %.1f dB\n", scene.name.c_str(), e.psnr_db);
    EXPECT_GE(e.psnr_db, 40.0) << scene.name;
  }
}

TEST(CompactScene, ImageDoesNotDependOnTheSplit) {
  const Scene scene = sphere_scene();
  const RenderSettings settings{.spp = 2, .max_bounces = 4};
  const Framebuffer one =
      testing::render_regions(scene, 61, 37, settings, {{0, 0, 61, 37}}, 1, 1, 0, true);
  const Framebuffer split = testing::render_regions(
      scene, 61, 37, settings, {{0, 0, 13, 37}, {13, 0, 61, 20}, {13, 20, 61, 37}}, 3, 2, 0, true);
  EXPECT_TRUE(identical(one, split));
}

TEST(CompactScene, IsSmallerThanFullPrecisionAndReportsItsBytes) {
  const Scene scene = sphere_scene();
  SceneCache cache(scene);
  const CpuDevice full(cache, CpuDeviceOptions{}, "cpu");
  const CpuDevice small(cache, CpuDeviceOptions{.compact = true}, "cpu:compact=1");
  EXPECT_EQ(full.info().representation, "embree");
  EXPECT_EQ(small.info().representation, "compact");
  EXPECT_GT(small.info().scene_bytes, 0u);
  EXPECT_LT(2 * small.info().scene_bytes, full.info().scene_bytes);
  const CompactScene& c = cache.compact_scene();
  EXPECT_LT(compact_bytes(c).total(), full_precision_bytes(scene, c.bvh.nodes.size()).total());
  // The estimates made before building are upper bounds of what is built.
  EXPECT_GE(estimate_compact_bytes(scene).total(), compact_bytes(c).total());
}

TEST(CompactScene, MemoryLimitRefusesWhatDoesNotFitUnlessCompactFits) {
  // A limit between what the sphere needs compact and at full precision.
  const Scene scene = make_lit_sphere(0.8f, 128, 256, true);
  SceneCache cache(scene);
  const uint64_t limit =
      (estimate_scene_bytes(scene, true) + estimate_scene_bytes(scene, false)) / 2;
  try {
    CpuDevice d(cache, CpuDeviceOptions{.memory_limit = limit}, "cpu:mem=1M");
    FAIL() << "a scene over the limit was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("emulated"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("compact=1 would need"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  const CpuDevice d(cache, CpuDeviceOptions{.compact = true, .memory_limit = limit},
                    "cpu:compact=1:mem=1M");
  EXPECT_LE(d.info().scene_bytes, limit);
}

}  // namespace compact_test
}  // namespace multiray

namespace multiray {
namespace compact_test {

// The shared decoding (render/shared/compact_mesh.h, which the CPU's shading and the
// OpenCL kernels both use) gives what CompactMesh's own readers give, corner for corner:
// normals, material and uvs, on a mesh whose triangles have different uv shifts (the v
// shift sits past the u shift's bits in a packed entry) and on meshes without normals or
// uvs.
TEST(CompactMeshView, DecodesAsTheMeshsOwnReaders) {
  Scene tiling = make_lit_sphere(0.8f, 16, 32, true);
  tiling.uvs.clear();
  for (size_t v = 0; v < tiling.positions.size(); ++v)
    tiling.uvs.push_back({37.0f * float(v % 7) / 7.0f, -3.0f + 2.5f * float(v % 5)});
  Scene bare = make_cornell_box();
  bare.normals.clear();
  bare.uvs.clear();
  for (const Scene& scene : {tiling, bare}) {
    const CompactScene c = build_compact_scene(scene);
    const CompactMesh& m = c.mesh;
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      const TriangleShading d = decode_shading(c, t);
      ASSERT_EQ(d.material, m.material(t));
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(d.uv[k].x, m.uv(t, k).x) << scene.name << " " << t << " " << k;
        ASSERT_EQ(d.uv[k].y, m.uv(t, k).y) << scene.name << " " << t << " " << k;
        if (m.normals.empty()) continue;
        const Vec3 n = decode_normal(m.normals[m.vertex(t, k)]);
        ASSERT_TRUE(same(d.normal[k], n)) << scene.name << " " << t << " " << k;
      }
    }
  }
}

}  // namespace compact_test
}  // namespace multiray
