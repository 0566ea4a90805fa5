// Ray queries against the compact scene (compact_scene.h) on the CPU: the stack walk the
// OpenCL kernel runs with compact=1 (render/shared/bvh_walk.h, written once), over the
// tree with a 4-wide decode and slab test of both children (kernels/traverse_compact.cl
// does the same arithmetic a plane at a time). Child boxes are decoded from their parent's box on
// the way down (so the stack holds boxes), triangles from the quantized positions at each leaf
// test. Hits carry the same fields as Embree's (accel.h), the geometric normal computed as Embree
// computes it.
#pragma once

#include <vector>

#include "render/accel.h"
#include "render/compact_scene.h"

namespace multiray {

// `cutouts` is the scene whose materials and textures decide alpha cut-outs (as the
// Embree filter does), or null when no material has an alpha mode.
bool compact_intersect(const CompactScene& c, const Scene* cutouts, const Ray& ray, Hit& hit);
bool compact_occluded(const CompactScene& c, const Scene* cutouts, const Ray& ray);

// The compact tree with every child box and triangle decoded once into floats: the same
// tree, traversed by the same code, at full precision (the comparison Seo et al. make
// against their uncompressed tree; bench/compact_bench.cpp times it). Its hits are the
// compact traversal's, bit for bit, since it stores exactly the values that one decodes.
struct CompactFloatTree {
  struct Node {
    float planes[12];  // x, y, z: child 0 lower, child 1 lower, child 0 upper, child 1 upper
    uint32_t child[2];
  };
  std::vector<Node> nodes;      // as CompactBvh::nodes
  std::vector<uint32_t> prims;  // CompactBvh::prims unpacked
  // The textbook indexed mesh (what Seo et al.'s uncompressed tree holds): three 32-bit
  // vertex indices a triangle, float positions (the compact mesh's, decoded).
  std::vector<uint32_t> faces;
  std::vector<Vec3> positions;
  std::vector<Vec3> triangles;  // per slot of `prims`: v0, v0 - v1, v2 - v0 (no indirection)
};
CompactFloatTree decode_compact_tree(const CompactScene& c);
// `per_slot`: triangles from `triangles` instead of the indexed mesh.
bool compact_float_intersect(const CompactFloatTree& t, const CompactScene& c,
                             const Scene* cutouts, const Ray& ray, Hit& hit, bool per_slot);

}  // namespace multiray
