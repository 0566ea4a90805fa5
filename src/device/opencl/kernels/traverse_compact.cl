// The quantized BVH of the compact scene (render/compact_scene.h, compiled in with
// -DMR_COMPACT=1) as a tree for render/shared/bvh_walk.h, as render/compact_accel.cpp walks it: each
// node decodes its children's boxes from its own decoded box (so the box travels down
// the stack with the reference), and leaves test triangles decoded from the quantized
// mesh. The arithmetic of the planes and of the positions is the CPU's
// (render/shared/compact.h), with contraction off (render/shared/language.h), so the
// boxes are the conservative ones the host checked when it built the tree.

#ifdef MR_COMPACT

typedef struct {
  float3 lo, hi;
} NodeBox;
typedef struct {
  NodeBox box[2];
  uint child[2];
} NodeKids;

// The root's box; false when the tree is empty (nothing can be hit).
bool tree_root(const SceneData* sc, NodeBox* box) {
  box->lo = load3(sc->compact->root_lo), box->hi = load3(sc->compact->root_hi);
  return sc->compact->has_nodes != 0u;
}

// A corner of a child's box: codes q[0][k], q[1][k], q[2][k] (k: 0, 1 the children's
// lower corners, 2, 3 their upper).
float3 dequantize_corner(NodeBox b, const __global CompactNode* n, int k) {
  return (float3)(compact_dequantize_plane(b.lo.x, b.hi.x, n->q[0][k], k >= 2),
                  compact_dequantize_plane(b.lo.y, b.hi.y, n->q[1][k], k >= 2),
                  compact_dequantize_plane(b.lo.z, b.hi.z, n->q[2][k], k >= 2));
}

// Both children decoded, then tested.
int tree_children(const SceneData* sc, uint ref, NodeBox box, const Ray* ray, float3 inv_dir,
                  float tmax, float t[2], NodeKids* kids) {
  const __global CompactNode* n = &sc->cnodes[ref];
  int hits = 0;
  for (int c = 0; c < 2; ++c) {
    kids->child[c] = n->child[c];
    kids->box[c].lo = dequantize_corner(box, n, c);
    kids->box[c].hi = dequantize_corner(box, n, c + 2);
    if (box_hit(kids->box[c].lo, kids->box[c].hi, ray->org, inv_dir, ray->tmin, tmax, &t[c]))
      hits |= 1 << c;
  }
  return hits;
}

uint tree_child(const SceneData* sc, const NodeKids* kids, int c, NodeBox* box) {
  *box = kids->box[c];
  return kids->child[c];
}

// The triangle in leaf slot `slot` tested against the ray (tri_hit).
bool tree_leaf_hit(const SceneData* sc, uint slot, const Ray* ray, float* tmax, Hit* hit) {
  const uint prim = compact_read_bits(sc->prims, slot, sc->compact->prim_bits);
  const float3 v0 = compact_corner(&sc->cmesh, prim, 0);
  return tri_hit(sc, prim, v0, v0 - compact_corner(&sc->cmesh, prim, 1),
                 compact_corner(&sc->cmesh, prim, 2) - v0, ray, tmax, hit);
}

#endif  // MR_COMPACT
