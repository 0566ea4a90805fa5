// A binary BVH in one flat array, built on the host and traversed by the OpenCL kernel
// (device/opencl/kernels/traverse.cl); its records are render/shared/bvh_records.h's,
// one layout for both. The compact representation (compact_scene.h) quantizes this same tree.
#pragma once

#include <cstdint>
#include <vector>

#include "render/shared/bvh_records.h"
#include "scene/scene.h"

namespace multiray {

inline constexpr uint32_t kLeafBit = 0x80000000u;
inline constexpr int kLeafCountBits = 4;  // leaves of 1..16 triangles
inline constexpr uint32_t kMaxLeafTriangles = 1u << kLeafCountBits;
inline constexpr uint32_t kMaxFlatTriangles = 1u << (31 - kLeafCountBits);

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
