// A compact kd-tree over the compact mesh (compact_scene.h), built to compare with the
// quantized BVH on size and speed (issue 11: Seo, Park & Ihm, Sensors 2022, §3 compact a
// kd-tree). It is not used for rendering: bench/compact_bench measures it.
//
// Build: the SAH kd-tree of Wald & Havran, "On building fast kd-trees for ray tracing, and
// on doing that in O(N log N)" (IEEE RT 2006), in its O(N log^2 N) form: at every node the
// candidate planes of each axis (the bounds of the triangles clipped to the node's box,
// "perfect splits") are sorted and swept; planar triangles go to the cheaper side; a
// triangle that straddles the plane is referenced on both sides. Leaves hold the
// references (not the paper's variant with references kept in inner nodes).
//
// Layout, in the spirit of the paper: 8 bytes a node, children stored next to each other,
// and 32-bit triangle indices in one reference array.
//
// Traversal: the front-to-back stack traversal with a [t_near, t_far] interval per node
// (Havran's thesis, 2000, and pbrt), with the Moller-Trumbore test of compact_accel.cpp
// (same arithmetic, so hits match the BVH's). Alpha cut-outs are not handled.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/accel.h"
#include "render/compact_scene.h"

namespace multiray {

// 8 bytes. `link`: low 2 bits the split axis (0..2) or kKdLeaf; high 30 bits, in an
// inner node the index of its lower child (the upper child is the next node), in a leaf
// the offset of its first reference in CompactKdTree::refs. `payload`: in an inner node
// the split position (a float's bits), in a leaf the number of references.
struct KdNode {
  uint32_t payload;
  uint32_t link;
  bool leaf() const { return (link & 3u) == kLeaf; }
  int axis() const { return int(link & 3u); }
  uint32_t index() const { return link >> 2; }
  float split() const { return std::bit_cast<float>(payload); }
  uint32_t count() const { return payload; }
  static constexpr uint32_t kLeaf = 3;
};
static_assert(sizeof(KdNode) == 8, "8-byte kd-tree nodes");

// Node indices and reference offsets must fit in 30 bits.
inline constexpr uint32_t kMaxKdIndex = (1u << 30) - 1;
// The traversal's stack holds one entry per level.
inline constexpr int kMaxKdDepth = 64;

struct CompactKdTree {
  Bounds3 root;                // the scene's box (of the decoded triangles)
  std::vector<KdNode> nodes;   // nodes[0] is the root; empty: nothing can be hit
  std::vector<uint32_t> refs;  // triangle indices, in leaf order, with duplicates
  int depth = 0;               // levels below the root
  // Half-width of the slab each split plane is taken as in traversal (16 ulps of the
  // largest coordinate; see compact_kdtree.cpp): not part of the layout, like `root`.
  float pad = 0;
  size_t bytes() const { return nodes.size() * sizeof(KdNode) + refs.size() * 4; }
};

// The cost model is Wald & Havran's: traversal 15, triangle test 20, and a split with an
// empty side costs (1 - empty_bonus) of its SAH cost. A node becomes a leaf when no split
// is cheaper than testing all its triangles, when it holds `leaf_triangles` or fewer, or
// at `max_depth` (0: 8 + 1.3 log2 N, at most kMaxKdDepth).
struct KdBuildOptions {
  float traversal_cost = 15.0f;
  float intersection_cost = 20.0f;
  float empty_bonus = 0.2f;
  int leaf_triangles = 1;
  int max_depth = 0;
};

// Over the decoded positions of `mesh` (which the queries below must be given). Throws
// DeviceError when the tree needs more than 2^30 nodes or references.
CompactKdTree build_compact_kdtree(const CompactMesh& mesh, const KdBuildOptions& options = {});

// Closest hit within [ray.tmin, ray.tmax] (the fields of accel.h's Hit), and any hit.
bool kdtree_intersect(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray,
                      Hit& hit);
bool kdtree_occluded(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray);

}  // namespace multiray
