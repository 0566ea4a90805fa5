// The records of the acceleration structures a GPU-style backend walks itself, one layout
// for the host that builds them (render/flat_bvh.h, device/gpu_scene/scene_buffers.h) and
// the kernels that read them (kernels/traverse*.cl, shading.cl). Float arrays and 32-bit
// scalars only; sizes checked on both sides, offsets by the C++ side
// (render/scene_records.cpp).
#ifndef MULTIRAY_RENDER_SHARED_BVH_RECORDS_H
#define MULTIRAY_RENDER_SHARED_BVH_RECORDS_H

#ifdef __cplusplus
#include <cstddef>

#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// 64 bytes, one cache line: an interior node holding the boxes of both children, so a
// traversal step reads one line and tests two boxes. Nodes are in depth-first order from
// the root (nodes[0]). A child reference is either another node's index or a leaf:
// kLeafBit | first_triangle << kLeafCountBits | (count - 1). Leaves live only inside
// their parent, so a leaf costs no node of its own.
typedef struct {
  float lo[2][3];  // child boxes
  float hi[2][3];
  mr_uint child[2];  // child references, see above
  mr_uint pad[2];
} FlatNode;

// 48 bytes: what a Moller-Trumbore test needs, in leaf order. `prim` is the triangle's
// index in the Scene, so hits name the same triangle as on the CPU. The edges are Embree's
// own, v0 - v1 (`e1n`) and v2 - v0, so the kernel's geometric normal cross(e2, e1n) is
// computed as Embree computes Ng, down to the sign of zero components (which decides the
// tangent frame of an axis-aligned normal, and so the environment's cosine samples);
// the Moller-Trumbore test uses -e1n = v1 - v0, barycentrics (u, v) of v1 and v2.
typedef struct {
  float v0[3];
  mr_uint prim;
  float e1n[3];
  float pad0;
  float e2[3];
  float pad1;
} FlatTriangle;

// 20 bytes, a node of the compact scene's quantized BVH (render/compact_scene.h): the
// boxes of both children, each plane as q / 255 of the way across this node's own box
// (lower planes rounded down, upper up, so a child box always contains its triangles;
// compact.h decodes them), and the children's references as in FlatNode (`first`
// indexing the compact tree's triangle references). The codes are stored axis by axis in
// the order a 4-wide vector register takes them for the slab test of both children at
// once (render/compact_accel.cpp): q[axis] = child 0's lower plane, child 1's lower,
// child 0's upper, child 1's upper.
typedef struct {
  mr_uchar q[3][4];
  mr_uint child[2];
} CompactNode;

// 64 bytes, a triangle's shading record as stored at full precision: three corner
// normals, three corner uvs and the material; render/shading_data.h's TriangleShading
// byte for byte (checked in render/scene_records.cpp).
typedef struct {
  float normal[9];
  float uv[6];
  mr_uint material;
} StoredShading;

// The scalars of the compact scene (render/compact_scene.h): the position grid
// (PositionGrid; its cell-index table is an array of its own), the root node's box and
// the uv coding (UvCoding).
typedef struct {
  float origin[3];
  float cell;
  float root_lo[3];
  mr_uint has_nodes;  // 0: the tree is empty, nothing can be hit
  float root_hi[3];
  mr_uint has_normals;  // 0: the mesh has no normals, shading uses the face normal
  float uv_step[2];
  mr_uint uv_period_log2[2];
  float step;  // PositionGrid::step: cell / 1023
  // Bit widths of the packed arrays (render/compact_packed.h): vertex index in bits 0-7,
  // material id 8-15, uv shift offsets u 16-23 and v 24-31.
  mr_uint widths;
  mr_int uv_shift_base[2];
  mr_uint prim_bits;  // width of the tree's packed triangle references
  mr_uint has_uvs;    // 0: the mesh has no uvs (the uv codes are a placeholder)
  mr_uint pad[2];
} CompactInfo;

MR_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(multiray::FlatNode) == 64, "kernel expects 64-byte nodes");
static_assert(sizeof(multiray::FlatTriangle) == 48, "kernel expects 48-byte triangles");
static_assert(sizeof(multiray::CompactInfo) == 96);
static_assert(sizeof(multiray::CompactNode) == 20 && offsetof(multiray::CompactNode, q) == 0,
              "kernels expect 20-byte nodes, the codes first");
static_assert(sizeof(multiray::StoredShading) == 64);
#else
typedef char mr_flat_node_is_64_bytes[sizeof(FlatNode) == 64 ? 1 : -1];
typedef char mr_flat_triangle_is_48_bytes[sizeof(FlatTriangle) == 48 ? 1 : -1];
typedef char mr_compact_info_is_96_bytes[sizeof(CompactInfo) == 96 ? 1 : -1];
typedef char mr_compact_node_is_20_bytes[sizeof(CompactNode) == 20 ? 1 : -1];
typedef char mr_stored_shading_is_64_bytes[sizeof(StoredShading) == 64 ? 1 : -1];
#endif

#endif  // MULTIRAY_RENDER_SHARED_BVH_RECORDS_H
