// The stack walk of a binary BVH, written once for the CPU's compact traversal
// (render/compact_accel.cpp) and the OpenCL kernels (kernels/traverse.cl's flat BVH,
// traverse_compact.cl's quantized one), in render/shared/language.h's dialect: nearer
// child first, a pending subtree popped only while it may still hold a closer hit.
//
// A tree provides, as free functions over a pointer to it (C++: overloads found by
// argument-dependent lookup, the template's `Tree`; OpenCL C: the one tree compiled in,
// whose "tree" is its SceneData):
//   bool tree_root(tree, Box* box)    the root's box; false when the tree is empty
//   int tree_children(tree, ref, box, ray, inv_dir, tmax, t[2], Kids* kids)
//                                     node `ref` (own box `box`): slab tests of both
//                                     children; bit c set when the ray meets child c,
//                                     entering at t[c]; `kids` keeps what tree_child needs
//   uint tree_child(tree, kids, c, Box* box)   child c's reference, and its box
//   bool tree_leaf_hit(tree, slot, ray, float* tmax, Hit* hit)
//                                     the triangle in leaf slot `slot`: updates *tmax and
//                                     *hit on a hit in (tmin, *tmax) that is not cut out
// Box is what the walk carries down with a reference (the quantized tree decodes a
// child's box from its parent's; a tree storing its boxes carries nothing).
#ifndef MULTIRAY_RENDER_SHARED_BVH_WALK_H
#define MULTIRAY_RENDER_SHARED_BVH_WALK_H

#ifdef __cplusplus
#include "render/shared/language.h"
#include "render/shared/ray.h"
#endif

// A child reference is a node's index or a leaf: MR_LEAF_BIT | first << MR_LEAF_COUNT_BITS
// | (count - 1) (render/flat_bvh.h's kLeafBit, kLeafCountBits; kMaxBvhDepth levels).
#define MR_LEAF_BIT 0x80000000u
#define MR_LEAF_COUNT_BITS 4
#define MR_BVH_STACK 64

#ifdef MR_OPENCL_C
#define MR_TREE_FUNCTION
#define MR_TREE const SceneData
#define MR_TREE_BOX NodeBox
#define MR_TREE_KIDS NodeKids
#else
#define MR_TREE_FUNCTION template <class Tree>
#define MR_TREE const Tree
#define MR_TREE_BOX typename Tree::Box
#define MR_TREE_KIDS typename Tree::Kids
#endif

MR_NAMESPACE_BEGIN

// Closest hit (any_hit false) or any hit (true, for shadow rays) along `ray` in `tree`.
MR_TREE_FUNCTION bool bvh_walk(MR_TREE* tree, const Ray* ray, bool any_hit, Hit* hit) {
  MR_TREE_BOX box;
  if (!tree_root(tree, &box)) return false;
  struct {
    mr_uint ref;
    float t;  // where the ray enters the subtree
    MR_TREE_BOX box;
  } stack[MR_BVH_STACK];
  const mr_float3 inv_dir = safe_inverse(ray->dir);
  float tmax = ray->tmax;
  int sp = 0;
  mr_uint ref = 0u;  // the root node
  bool found = false;
  for (;;) {
    if (ref & MR_LEAF_BIT) {
      const mr_uint first = (ref & ~MR_LEAF_BIT) >> MR_LEAF_COUNT_BITS;
      const mr_uint count = (ref & ((1u << MR_LEAF_COUNT_BITS) - 1u)) + 1u;
      for (mr_uint i = first; i < first + count; ++i)
        if (tree_leaf_hit(tree, i, ray, &tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    } else {
      float t[2];
      MR_TREE_KIDS kids;
      const int h = tree_children(tree, ref, box, ray, inv_dir, tmax, t, &kids);
      if (h != 0) {
        const int nearer = h == 3 ? (t[1] < t[0] ? 1 : 0) : h - 1;  // or the only child hit
        if (h == 3) {
          stack[sp].ref = tree_child(tree, &kids, 1 - nearer, &stack[sp].box);
          stack[sp].t = t[1 - nearer];
          ++sp;
        }
        ref = tree_child(tree, &kids, nearer, &box);
        continue;
      }
    }
    for (;;) {  // the nearest pending subtree that can still hold a closer hit
      if (sp == 0) return found;
      --sp;
      if (stack[sp].t <= tmax) break;
    }
    ref = stack[sp].ref, box = stack[sp].box;
  }
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_BVH_WALK_H
