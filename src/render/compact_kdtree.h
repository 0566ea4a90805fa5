// A compact kd-tree over the compact mesh (compact_scene.h), built to compare with the
// quantized BVH on size and speed (issue 11: Seo, Park & Ihm, Sensors 2022, §3 compact a
// kd-tree). It is not used for rendering: bench/compact_bench measures it.
//
// Build: the SAH kd-tree of Wald & Havran, "On building fast kd-trees for ray tracing, and
// on doing that in O(N log N)" (IEEE RT 2006), in its O(N log^2 N) form: at every node the
// candidate planes of each axis (the bounds of the triangles clipped to the node's box,
// "perfect splits") are sorted and swept; planar triangles go to the cheaper side; a
// triangle that straddles the plane is referenced on both sides.
//
// Two forms (KdBuildOptions::inner_refs_max):
// - 0: Wald & Havran's leaf-only tree, every reference in a leaf.
// - 1 or 2 (default 2): after Choi, Chang & Ihm, "Improving memory space efficiency of
//   kd-tree for real-time ray tracing" (CGF 32(7), PG 2013), whose inner nodes keep one
//   such triangle; two per inner node is Seo, Kim & Ihm's form (Sensors 2022), the
//   default here. An inner node may keep up to that many of the triangles that
//   straddle its split plane, instead of referencing them in both subtrees (where they
//   would be cut again and again); the traversal tests them when it visits the node. At
//   most path_refs_max such references lie on any root-to-leaf path. Which straddlers are
//   kept is decided by two measures against thresholds (tau_occu, tau_freq); the paper's
//   text was not at hand, so their definitions are OUR reading, written down once, in
//   compact_kdtree_inner.h.
//
// Layout, in the spirit of the paper: 8 bytes a node, children stored next to each other,
// 32-bit triangle indices in one reference array for the leaves, and an inner node's 1-2
// references in one 8-byte slot stored just before its children (see KdNode).
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

// 8 bytes. `link`'s low 2 bits: the split axis (0..2) or kKdLeaf.
// - Leaf: link's high 30 bits the offset of its first reference in CompactKdTree::refs,
//   `payload` the number of references.
// - Inner node: `payload` the split position (a float's bits); link bit 2 set when the node
//   keeps references of its own; link's high 29 bits the index of its lower child, the
//   upper child being the next node. When bit 2 is set, the node before the lower child is
//   a reference slot, not a node: its two words are triangle indices, the second kNoRef
//   when it holds one. So a node with references costs 8 more bytes, the same as two
//   32-bit references, and needs no offset of its own.
struct KdNode {
  uint32_t payload;
  uint32_t link;
  bool leaf() const { return (link & 3u) == kLeaf; }
  int axis() const { return int(link & 3u); }
  float split() const { return std::bit_cast<float>(payload); }
  // Inner nodes.
  bool has_refs() const { return (link & 4u) != 0; }
  uint32_t children() const { return link >> 3; }
  // Leaves.
  uint32_t index() const { return link >> 2; }
  uint32_t count() const { return payload; }
  // A reference slot's triangles (the second may be kNoRef).
  uint32_t first_ref() const { return payload; }
  uint32_t second_ref() const { return link; }
  static constexpr uint32_t kLeaf = 3;
  static constexpr uint32_t kNoRef = 0xffffffffu;
};
static_assert(sizeof(KdNode) == 8, "8-byte kd-tree nodes");

// Reference offsets must fit in 30 bits, node indices in 29.
inline constexpr uint32_t kMaxKdIndex = (1u << 30) - 1;
inline constexpr uint32_t kMaxKdNode = (1u << 29) - 1;
// The traversal's stack holds one entry per level.
inline constexpr int kMaxKdDepth = 64;
// An inner node's references fit one slot.
inline constexpr int kMaxKdInnerRefs = 2;

struct CompactKdTree {
  Bounds3 root;                // the scene's box (of the decoded triangles)
  std::vector<KdNode> nodes;   // nodes[0] is the root, reference slots included; empty:
                               // nothing can be hit
  std::vector<uint32_t> refs;  // leaves' triangle indices, in leaf order, with duplicates
  size_t slots = 0;            // reference slots among `nodes`
  size_t inner_refs = 0;       // triangle references in those slots
  int depth = 0;               // levels below the root
  // Half-width of the slab each split plane is taken as in traversal (16 ulps of the
  // largest coordinate; see compact_kdtree.cpp): not part of the layout, like `root`.
  float pad = 0;
  // Everything the traversal reads: nodes and slots (8 bytes each) and leaf references.
  size_t bytes() const { return nodes.size() * sizeof(KdNode) + refs.size() * 4; }
  size_t tree_nodes() const { return nodes.size() - slots; }
  size_t all_refs() const { return refs.size() + inner_refs; }
};

// The cost model is Wald & Havran's: traversal 15, triangle test 20, and a split with an
// empty side costs (1 - empty_bonus) of its SAH cost. A node becomes a leaf when no split
// is cheaper than testing all its triangles, when it holds `leaf_triangles` or fewer, or
// at `max_depth` (0: 8 + 1.3 log2 N, at most kMaxKdDepth). The last four choose the form
// (see the top of this file; compact_kdtree_inner.h defines the two measures).
struct KdBuildOptions {
  float traversal_cost = 15.0f;
  float intersection_cost = 20.0f;
  float empty_bonus = 0.2f;
  int leaf_triangles = 1;
  int max_depth = 0;
  int inner_refs_max = 2;  // per inner node, 0..kMaxKdInnerRefs; 0: leaf-only tree
  int path_refs_max = 8;   // inner references on any root-to-leaf path
  float tau_occu = 0.5f;   // least occupancy of a kept triangle
  float tau_freq = 0.4f;   // least frequency of a kept triangle
};

// Over the decoded positions of `mesh` (which the queries below must be given). Throws
// DeviceError when the tree needs more than 2^29 nodes or 2^30 leaf references, and
// std::invalid_argument when inner_refs_max is outside 0..kMaxKdInnerRefs.
CompactKdTree build_compact_kdtree(const CompactMesh& mesh, const KdBuildOptions& options = {});

// Closest hit within [ray.tmin, ray.tmax] (the fields of accel.h's Hit), and any hit.
bool kdtree_intersect(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray,
                      Hit& hit);
bool kdtree_occluded(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray);

}  // namespace multiray
