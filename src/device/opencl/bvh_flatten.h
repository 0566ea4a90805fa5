// A binary BVH in one flat array, built on the host and traversed by the OpenCL kernel
// (kernels/traverse.cl). The layout is part of the kernel's contract: change both together.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace multiray {

// 32 bytes. Nodes are in depth-first order: an interior node's first child is the next
// node in the array, so only the second child's index is stored.
struct FlatNode {
  float lo[3];
  uint32_t offset;  // leaf: first triangle in FlatBvh::triangles; interior: second child
  float hi[3];
  uint32_t count;  // leaf: number of triangles (> 0); interior: 0
};
static_assert(sizeof(FlatNode) == 32, "kernel expects 32-byte nodes");

// 48 bytes: what a Moller-Trumbore test needs, in leaf order. `prim` is the triangle's
// index in the Scene, so hits name the same triangle as on the CPU, and the edges are
// v1 - v0 and v2 - v0, so barycentrics (u, v) and the geometric normal cross(e1, e2)
// follow the CPU's (Embree's) convention.
struct FlatTriangle {
  float v0[3];
  uint32_t prim;
  float e1[3];
  float pad0;
  float e2[3];
  float pad1;
};
static_assert(sizeof(FlatTriangle) == 48, "kernel expects 48-byte triangles");

struct FlatBvh {
  std::vector<FlatNode> nodes;          // nodes[0] is the root
  std::vector<FlatTriangle> triangles;  // zero-area triangles are left out (never hit)
  int depth = 0;                        // levels from the root to the deepest leaf
};

// The kernel's traversal stack holds this many entries; a deeper tree cannot be rendered.
inline constexpr int kMaxBvhDepth = 64;

// Builds a SAH BVH over every non-degenerate triangle of `scene` with Embree's
// rtcBuildBVH (binned SAH, user-defined nodes) and flattens it. Throws DeviceError when
// Embree fails or the tree is deeper than kMaxBvhDepth.
FlatBvh build_flat_bvh(const Scene& scene);

}  // namespace multiray
