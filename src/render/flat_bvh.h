// A binary BVH in one flat array, built on the host and traversed by the OpenCL kernel
// (device/opencl/kernels/traverse.cl); the layout is part of the kernel's contract, change
// both together. The compact representation (compact_scene.h) quantizes this same tree.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace multiray {

// 64 bytes, one cache line: an interior node holding the boxes of both children, so a
// traversal step reads one line and tests two boxes. Nodes are in depth-first order from
// the root (nodes[0]). A child reference is either another node's index or a leaf:
// kLeafBit | first_triangle << kLeafCountBits | (count - 1). Leaves live only inside
// their parent, so a leaf costs no node of its own.
struct alignas(64) FlatNode {
  float lo[2][3];  // child boxes
  float hi[2][3];
  uint32_t child[2];  // child references, see above
  uint32_t pad[2];
};
static_assert(sizeof(FlatNode) == 64, "kernel expects 64-byte nodes");

inline constexpr uint32_t kLeafBit = 0x80000000u;
inline constexpr int kLeafCountBits = 4;  // leaves of 1..16 triangles
inline constexpr uint32_t kMaxLeafTriangles = 1u << kLeafCountBits;
inline constexpr uint32_t kMaxFlatTriangles = 1u << (31 - kLeafCountBits);

// 48 bytes: what a Moller-Trumbore test needs, in leaf order. `prim` is the triangle's
// index in the Scene, so hits name the same triangle as on the CPU. The edges are Embree's
// own, v0 - v1 (`e1n`) and v2 - v0, so the kernel's geometric normal cross(e2, e1n) is
// computed as Embree computes Ng, down to the sign of zero components (which decides the
// tangent frame of an axis-aligned normal, and so the environment's cosine samples);
// the Moller-Trumbore test uses -e1n = v1 - v0, barycentrics (u, v) of v1 and v2.
struct FlatTriangle {
  float v0[3];
  uint32_t prim;
  float e1n[3];
  float pad0;
  float e2[3];
  float pad1;
};
static_assert(sizeof(FlatTriangle) == 48, "kernel expects 48-byte triangles");

struct FlatBvh {
  std::vector<FlatNode> nodes;          // nodes[0] is the root (never empty)
  std::vector<FlatTriangle> triangles;  // zero-area triangles are left out (never hit)
  int depth = 0;                        // nodes from the root to the deepest leaf's parent
};

// The kernel's traversal stack holds this many entries; a deeper tree cannot be rendered.
inline constexpr int kMaxBvhDepth = 64;

// Builds a SAH BVH over every non-degenerate triangle of `scene` with Embree's
// rtcBuildBVH (binned SAH, user-defined nodes) and flattens it. Throws DeviceError when
// Embree fails, the tree is deeper than kMaxBvhDepth or the scene has more than
// kMaxFlatTriangles triangles.
FlatBvh build_flat_bvh(const Scene& scene);

}  // namespace multiray
