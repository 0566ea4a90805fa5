#include "render/compact_scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "core/error.h"
#include "render/flat_bvh.h"

namespace multiray {

CompactMesh::Parts CompactMesh::parts() const {
  Parts p;
  p.positions = positions.size() * sizeof(QuantizedPosition);
  p.cell_table = grid.table_bytes();
  p.normals = normals.size() * 2;
  p.uvs = uvs.size() * 2;
  p.uv_shifts = uv_shifts.bytes();
  p.faces = indices.bytes();
  p.materials = material_ids.bytes();
  return p;
}

namespace {

// Vertices of `s` merged where the loader duplicated them: same position, normal and uv
// bits (so every corner decodes as its own vertex would). `first` lists, per welded
// vertex, the scene vertex it stands for (the first of its copies, so the order is the
// scene's); `remap` gives every scene vertex's welded index.
struct Welded {
  std::vector<uint32_t> first, remap;
};

Welded weld_vertices(const Scene& s) {
  using Key = std::array<uint32_t, 8>;
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0xcbf29ce484222325ull;
      for (uint32_t x : k) h = (h ^ x) * 0x100000001b3ull;
      return size_t(h ^ (h >> 29));
    }
  };
  const auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
  std::unordered_map<Key, uint32_t, KeyHash> index;
  index.reserve(s.positions.size());
  Welded w;
  w.remap.resize(s.positions.size());
  for (size_t v = 0; v < s.positions.size(); ++v) {
    Key k{};
    const Vec3 p = s.positions[v];
    k[0] = bits(p.x), k[1] = bits(p.y), k[2] = bits(p.z);
    if (!s.normals.empty()) {
      const Vec3 n = s.normals[v];
      k[3] = bits(n.x), k[4] = bits(n.y), k[5] = bits(n.z);
    }
    if (!s.uvs.empty()) k[6] = bits(s.uvs[v].x), k[7] = bits(s.uvs[v].y);
    const auto [it, added] = index.emplace(k, uint32_t(w.first.size()));
    if (added) w.first.push_back(uint32_t(v));
    w.remap[v] = it->second;
  }
  return w;
}

}  // namespace

CompactMesh build_compact_mesh(const Scene& scene) {
  if (scene.materials.size() > 65535)
    throw InputError("the compact representation holds at most 65,535 materials, the scene has " +
                     std::to_string(scene.materials.size()));
  const Welded w = weld_vertices(scene);
  std::vector<Vec3> positions;
  std::vector<Vec2> uvs;
  positions.reserve(w.first.size());
  for (uint32_t v : w.first) positions.push_back(scene.positions[v]);
  if (!scene.uvs.empty())
    for (uint32_t v : w.first) uvs.push_back(scene.uvs[v]);
  std::vector<uint32_t> indices(scene.indices.size());
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = w.remap[scene.indices[i]];

  CompactMesh m;
  // The table's limit counts the scene's vertices, not the welded ones: the grid, and so
  // every decoded position, is the one the scene's own vertices give (welding loses
  // nothing; the welded vertices are the same point set).
  m.grid = PositionGrid::fit(positions, geometry_cell_limit(scene.positions.size()));
  m.positions.reserve(positions.size());
  for (const Vec3& p : positions) m.positions.push_back(encode_position(m.grid, p));
  if (!scene.normals.empty())
    for (uint32_t v : w.first) m.normals.push_back(encode_normal(scene.normals[v]));
  if (!uvs.empty()) {
    QuantizedUvs q = quantize_uvs(uvs, indices);
    m.uv_coding = q.coding;
    m.uvs = std::move(q.codes);
    m.uv_shifts = std::move(q.shifts);
  }
  m.indices =
      PackedUints::pack(indices, bits_for(uint32_t(std::max<size_t>(positions.size(), 1) - 1)));
  m.material_ids = PackedUints::pack(scene.material_ids);
  return m;
}

uint8_t quantize_plane(float lo, float hi, float value, bool upper) {
  if (!(hi > lo)) return upper ? 255 : 0;
  const float f = (value - lo) / (hi - lo) * 255.0f;
  int q = int(upper ? std::ceil(f) : std::floor(f));
  q = std::clamp(q, 0, 255);
  if (upper)
    while (q < 255 && compact_dequantize_plane(lo, hi, uint8_t(q), true) < value) ++q;
  else
    while (q > 0 && compact_dequantize_plane(lo, hi, uint8_t(q), false) > value) --q;
  return uint8_t(q);
}

namespace {

// Quantizes the children of flat node `index`, whose decoded box is `box`, and recurses
// into interior children with their decoded boxes.
void quantize_subtree(const FlatBvh& flat, uint32_t index, const Bounds3& box,
                      std::vector<CompactNode>& out) {
  const FlatNode& f = flat.nodes[index];
  CompactNode& n = out[index];
  const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
  Bounds3 child_box[2];
  for (int c = 0; c < 2; ++c) {
    float dlo[3], dhi[3];
    for (int a = 0; a < 3; ++a) {
      n.q[a][c] = quantize_plane(lo[a], hi[a], f.lo[c][a], false);
      n.q[a][2 + c] = quantize_plane(lo[a], hi[a], f.hi[c][a], true);
      dlo[a] = compact_dequantize_plane(lo[a], hi[a], n.q[a][c], false);
      dhi[a] = compact_dequantize_plane(lo[a], hi[a], n.q[a][2 + c], true);
    }
    child_box[c].lo = Vec3(dlo[0], dlo[1], dlo[2]);
    child_box[c].hi = Vec3(dhi[0], dhi[1], dhi[2]);
    n.child[c] = f.child[c];
  }
  for (int c = 0; c < 2; ++c)
    if (!(f.child[c] & kLeafBit)) quantize_subtree(flat, f.child[c], child_box[c], out);
}

// The mesh and its tree (the scalars are filled by build_compact_scene).
CompactScene build_mesh_and_tree(const Scene& scene) {
  CompactScene c;
  c.mesh = build_compact_mesh(scene);
  // The tree is built over the decoded positions: its boxes must bound what is tested.
  Scene decoded;
  decoded.indices = c.mesh.indices.unpacked();
  decoded.positions.reserve(scene.positions.size());
  for (uint32_t v = 0; v < c.mesh.positions.size(); ++v)
    decoded.positions.push_back(c.mesh.position(v));
  // A scene whose triangles all lost their area (all vertices equal, say) has an empty
  // tree: every ray misses, as Embree's full-precision traversal would have it.
  bool any_area = false;
  for (uint32_t t = 0; t < scene.triangle_count() && !any_area; ++t) {
    const Vec3 a = c.mesh.corner(t, 0), b = c.mesh.corner(t, 1), d = c.mesh.corner(t, 2);
    const Vec3 n = cross(b - a, d - a);
    any_area = n.x != 0 || n.y != 0 || n.z != 0;
  }
  if (!any_area) return c;
  const FlatBvh flat = build_flat_bvh(decoded);
  c.bvh.depth = flat.depth;
  std::vector<uint32_t> prims;
  prims.reserve(flat.triangles.size());
  for (const FlatTriangle& t : flat.triangles) prims.push_back(t.prim);
  c.bvh.prims = PackedUints::pack(
      prims, bits_for(uint32_t(std::max<size_t>(scene.triangle_count(), 1) - 1)));
  const FlatNode& r = flat.nodes[0];
  c.bvh.root.lo = Vec3(std::min(r.lo[0][0], r.lo[1][0]), std::min(r.lo[0][1], r.lo[1][1]),
                       std::min(r.lo[0][2], r.lo[1][2]));
  c.bvh.root.hi = Vec3(std::max(r.hi[0][0], r.hi[1][0]), std::max(r.hi[0][1], r.hi[1][1]),
                       std::max(r.hi[0][2], r.hi[1][2]));
  c.bvh.nodes.resize(flat.nodes.size());
  quantize_subtree(flat, 0, c.bvh.root, c.bvh.nodes);
  return c;
}

void put(float out[3], Vec3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

CompactInfo compact_info(const CompactScene& c) {
  const CompactMesh& m = c.mesh;
  CompactInfo i{};
  put(i.origin, m.grid.origin);
  i.cell = m.grid.cell;
  i.step = m.grid.step;
  i.has_normals = m.normals.empty() ? 0u : 1u;
  i.has_uvs = m.uvs.empty() ? 0u : 1u;
  i.has_nodes = c.bvh.nodes.empty() ? 0u : 1u;
  put(i.root_lo, c.bvh.root.lo), put(i.root_hi, c.bvh.root.hi);
  for (int a = 0; a < 2; ++a)
    i.uv_step[a] = m.uv_coding.step[a], i.uv_period_log2[a] = m.uv_coding.period_log2[a],
    i.uv_shift_base[a] = m.uv_shifts.base[a];
  i.widths = m.indices.width | m.material_ids.width << 8 | m.uv_shifts.bits[0] << 16 |
             m.uv_shifts.bits[1] << 24;
  i.prim_bits = c.bvh.prims.width;
  return i;
}

}  // namespace

CompactScene build_compact_scene(const Scene& scene) {
  CompactScene c = build_mesh_and_tree(scene);
  c.info = compact_info(c);
  return c;
}

CompactMeshView CompactScene::view() const {
  static_assert(sizeof(QuantizedPosition) == 3 * sizeof(uint16_t));
  const CompactMesh& m = mesh;
  return CompactMeshView{&info,
                         reinterpret_cast<const uint16_t*>(m.positions.data()),
                         m.grid.cells.data(),
                         m.indices.words.data(),
                         m.normals.data(),
                         m.uvs.data(),
                         m.uv_shifts.packed.words.data(),
                         m.material_ids.words.data()};
}

SceneBytes full_precision_bytes(const Scene& s, size_t tree_nodes) {
  SceneBytes b;
  b.mesh = s.positions.size() * 12 + s.normals.size() * 12 + s.uvs.size() * 8 +
           s.indices.size() * 4 + s.material_ids.size() * 4;
  b.structure = tree_nodes * sizeof(FlatNode) + s.triangle_count() * 4;
  return b;
}

namespace {

size_t packed_bytes(size_t count, uint32_t width) {
  return (uint64_t(count) * width + 31) / 32 * 4;
}

}  // namespace

SceneBytes estimate_compact_bytes(const Scene& s) {
  SceneBytes b;
  // Welding can only lower the vertex count, so the scene's own counts bound every
  // per-vertex part and the width of the faces. The cell table at its largest: a geometry
  // cell per vertex, at most 2^16, each three 16-bit coordinates. Uv shifts at their
  // widest: 16 bits per component.
  uint32_t largest_material = 0;
  for (uint32_t id : s.material_ids) largest_material = std::max(largest_material, id);
  const uint32_t index_bits = bits_for(uint32_t(std::max<size_t>(s.positions.size(), 1) - 1));
  b.mesh = s.positions.size() * sizeof(QuantizedPosition) +
           std::min(s.positions.size(), size_t(kMaxGridCells)) * 6 + s.normals.size() * 2 +
           s.uvs.size() * 4 + (s.uvs.empty() ? 0 : packed_bytes(s.triangle_count(), 32)) +
           packed_bytes(s.indices.size(), index_bits) +
           packed_bytes(s.material_ids.size(), bits_for(largest_material));
  b.structure = s.triangle_count() * (sizeof(CompactNode) + 4);
  return b;
}

SceneBytes compact_bytes(const CompactScene& c) {
  return SceneBytes{c.mesh.bytes(), c.bvh.bytes()};
}

}  // namespace multiray
