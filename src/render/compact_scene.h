// The compact scene representation (Seo, Park & Ihm, Sensors 2022, §3): a quantized mesh
// (compact_quantize.h) and a quantized BVH, so that a device with little memory can hold a
// large scene. A device opts in per device (`compact=1` in its --devices spec); the image
// it renders differs from the full-precision one by the quantization only, and is
// bit-identical for any split among devices of the same type and representation.
//
// The acceleration structure. The paper compacts a kd-tree; we quantize our own binary
// BVH (render/flat_bvh.h, Embree's binned SAH builder) instead, as compressed wide BVHs do
// (Ylitie, Karras & Laine, HPG 2017): each node stores its two children's boxes in 8 bits
// per plane relative to its own box (20 bytes a node instead of 64), and leaves refer to
// triangles by bit-packed index instead of holding copies of their vertices (17 bits a
// triangle for 100,000 triangles, instead of 48 bytes). Why not the kd-tree: the renderer's
// traversals are BVH traversals, a kd-tree would duplicate references of triangles that straddle a
// split, and our measurements (docs/compact.md) put the quantized BVH under the goal without one.
//
// The tree is built over the *decoded* positions, so its boxes bound the triangles the
// traversal actually tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "render/compact_packed.h"
#include "render/compact_quantize.h"
#include "render/shared/compact_mesh.h"
#include "scene/scene.h"

namespace multiray {

// The quantized mesh. Vertices that the loader duplicated with the same position, normal
// and uv are stored once (welded; the full-precision scene keeps its own vertices), and
// the per-triangle arrays are bit-packed (render/compact_packed.h): faces in the bits of
// the largest vertex index, material ids in the bits of the largest id, uv shifts relative
// to the smallest shift. Each keeps random access, as the paper's faces do.
struct CompactMesh {
  PositionGrid grid;                         // with the cell-index table of the geometry cells
  std::vector<QuantizedPosition> positions;  // one per welded vertex
  std::vector<uint16_t> normals;             // one octahedral code per position, or empty
  UvCoding uv_coding;
  std::vector<uint16_t> uvs;  // two codes per position, or empty
  UvShifts uv_shifts;         // one entry per triangle when there are uvs
  PackedUints indices;        // three vertex indices per triangle, as Scene::indices
  PackedUints material_ids;   // one per triangle

  size_t triangle_count() const { return indices.size() / 3; }
  uint32_t vertex(uint32_t tri, int k) const { return indices[3 * size_t(tri) + size_t(k)]; }
  uint32_t material(uint32_t tri) const { return material_ids[tri]; }
  Vec3 position(uint32_t v) const { return decode_position(grid, positions[v]); }
  Vec3 corner(uint32_t tri, int k) const { return position(vertex(tri, k)); }
  // The uv of corner `k` of triangle `tri` (zero without uvs).
  Vec2 uv(uint32_t tri, int k) const {
    return uvs.empty() ? Vec2{}
                       : decode_uv(uv_coding, uv_shifts, tri, &uvs[2 * size_t(vertex(tri, k))]);
  }
  // Bytes by part (the memory reports: docs/compact.md, bench/compact_bench.cpp).
  struct Parts {
    size_t positions = 0, cell_table = 0, normals = 0, uvs = 0, uv_shifts = 0, faces = 0,
           materials = 0;
    size_t total() const {
      return positions + cell_table + normals + uvs + uv_shifts + faces + materials;
    }
  };
  Parts parts() const;
  size_t bytes() const { return parts().total(); }
};

// The tree: its nodes are render/shared/bvh_records.h's CompactNode (20 bytes, 8-bit
// planes of both children's boxes relative to the node's own box).
struct CompactBvh {
  Bounds3 root;                    // the root node's own box, at full precision
  std::vector<CompactNode> nodes;  // nodes[0] is the root; empty: nothing can be hit
  // Scene triangle indices, in leaf order, bit-packed in the bits of the largest index
  // (ours: 17 bits a reference for 69,451 triangles instead of 32).
  PackedUints prims;
  int depth = 0;
  size_t bytes() const { return nodes.size() * sizeof(CompactNode) + prims.bytes(); }
};

// The code of plane `value` (in [lo, hi]) of a child's box: the tightest whose decoded
// plane lies on the safe side of `value` (at or below it for a lower plane, at or above
// it for an upper one), checked with compact_dequantize_plane, the traversal's own arithmetic.
uint8_t quantize_plane(float lo, float hi, float value, bool upper);

struct CompactScene {
  CompactMesh mesh;
  CompactBvh bvh;
  CompactInfo info;  // the scalars as the shared decoding reads them (render/shared/)
  size_t bytes() const { return mesh.bytes() + bvh.bytes(); }
  // The mesh as render/shared/compact_mesh.h reads it (pointing into this scene).
  CompactMeshView view() const;
};

// Sizes, in bytes, of the parts of a scene at full precision and compact, for the
// memory reports and the `mem=` check. Full precision counts the indexed mesh (float
// positions, normals and uvs, 32-bit indices and material ids) and the same tree with
// float boxes (FlatNode) and 32-bit triangle references: the textbook layout the paper
// compares against, not any one device's buffers.
struct SceneBytes {
  size_t mesh = 0, structure = 0;
  size_t total() const { return mesh + structure; }
};
SceneBytes full_precision_bytes(const Scene& scene, size_t tree_nodes);
// An estimate made before building (for refusing a device early): the tree's node count
// is taken as the triangle count, an upper bound for leaves of one triangle or more.
SceneBytes estimate_compact_bytes(const Scene& scene);
SceneBytes compact_bytes(const CompactScene& c);

// Throws InputError when the scene has more than 65,535 materials (a limit kept from the
// 16-bit material ids; the packed ids would hold more),
// DeviceError when the tree cannot be built (see build_flat_bvh).
CompactScene build_compact_scene(const Scene& scene);

// The mesh alone (for tests of the quantization): no tree.
CompactMesh build_compact_mesh(const Scene& scene);

}  // namespace multiray
