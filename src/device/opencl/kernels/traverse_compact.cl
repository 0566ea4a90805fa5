// The quantized BVH of the compact scene (render/compact_scene.h, compiled in with
// -DMR_COMPACT=1), traversed as render/compact_accel.cpp does: each node decodes its
// children's boxes from its own decoded box (so the box travels down the stack with the
// reference), and leaves test triangles decoded from the quantized mesh. The arithmetic
// of the planes and of decode_position is the CPU's (render/shared/compact.h), with
// contraction off (render/shared/language.h),
// so the boxes are the conservative ones the host checked when it built the tree.
// Then the ray queries the rest of the kernel uses, over whichever traversal is compiled.

#ifdef MR_COMPACT

// A plane of a child's box: render/shared/compact.h's, a lower plane (k: 0, 1) from the
// parent's lower plane, an upper one (k: 2, 3) from its upper plane.
float dequantize_plane(float lo, float hi, uint q, int k) {
  return k < 2 ? compact_dequantize_lower(lo, hi, q) : compact_dequantize_upper(lo, hi, q);
}

// A corner of a child's box: codes q[0][k], q[1][k], q[2][k] (k: 0, 1 the children's
// lower corners, 2, 3 their upper).
float3 dequantize_corner(float3 lo, float3 hi, const __global CompactNode* n, int k) {
  return (float3)(dequantize_plane(lo.x, hi.x, n->q[0][k], k),
                  dequantize_plane(lo.y, hi.y, n->q[1][k], k),
                  dequantize_plane(lo.z, hi.z, n->q[2][k], k));
}

bool compact_tri_hit(const SceneData* sc, uint prim, const Ray* ray, float* tmax, Hit* hit) {
  const float3 v0 = compact_corner(&sc->cmesh, prim, 0);
  return tri_hit(sc, prim, v0, v0 - compact_corner(&sc->cmesh, prim, 1),
                 compact_corner(&sc->cmesh, prim, 2) - v0, ray, tmax, hit);
}

bool traverse(const SceneData* sc, const Ray* ray, bool any_hit, Hit* hit) {
  const __global CompactInfo* info = sc->compact;
  if (!info->has_nodes) return false;
  const float3 inv_dir = safe_inverse(ray->dir);
  float tmax = ray->tmax;
  uint stack[STACK_SIZE];
  float stack_t[STACK_SIZE];        // entry distance of each stacked subtree
  float3 stack_lo[STACK_SIZE], stack_hi[STACK_SIZE];  // its decoded box
  int sp = 0;
  uint ref = 0;  // the root node, its box at full precision
  float3 lo = load3(info->root_lo), hi = load3(info->root_hi);
  bool found = false;
  for (;;) {
    bool descend = false;
    if (ref & LEAF_BIT) {
      const uint first = (ref & ~LEAF_BIT) >> LEAF_COUNT_BITS;
      const uint count = (ref & ((1u << LEAF_COUNT_BITS) - 1u)) + 1u;
      for (uint i = first; i < first + count; ++i)
        if (compact_tri_hit(sc, compact_read_bits(sc->prims, i, info->prim_bits), ray, &tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    } else {
      const __global CompactNode* n = &sc->cnodes[ref];
      const float3 lo0 = dequantize_corner(lo, hi, n, 0), hi0 = dequantize_corner(lo, hi, n, 2);
      const float3 lo1 = dequantize_corner(lo, hi, n, 1), hi1 = dequantize_corner(lo, hi, n, 3);
      float t0, t1;
      const bool h0 = box_hit(lo0, hi0, ray->org, inv_dir, ray->tmin, tmax, &t0);
      const bool h1 = box_hit(lo1, hi1, ray->org, inv_dir, ray->tmin, tmax, &t1);
      if (h0 && h1) {
        const int first_child = t1 < t0 ? 1 : 0;
        stack[sp] = n->child[1 - first_child];
        stack_t[sp] = first_child ? t0 : t1;
        stack_lo[sp] = first_child ? lo0 : lo1;
        stack_hi[sp] = first_child ? hi0 : hi1;
        ++sp;
        ref = n->child[first_child];
        lo = first_child ? lo1 : lo0;
        hi = first_child ? hi1 : hi0;
        descend = true;
      } else if (h0 || h1) {
        ref = n->child[h0 ? 0 : 1];
        lo = h0 ? lo0 : lo1;
        hi = h0 ? hi0 : hi1;
        descend = true;
      }
    }
    if (descend) continue;
    for (;;) {  // the nearest pending subtree that can still hold a closer hit
      if (sp == 0) return found;
      --sp;
      if (stack_t[sp] <= tmax) break;
    }
    ref = stack[sp];
    lo = stack_lo[sp];
    hi = stack_hi[sp];
  }
}

#endif  // MR_COMPACT

bool intersect_closest(const SceneData* sc, const Ray* ray, Hit* hit) {
  return traverse(sc, ray, false, hit);
}

bool occluded(const SceneData* sc, const Ray* ray) {
  Hit unused;
  return traverse(sc, ray, true, &unused);
}
