// Ray queries: the flat BVH (render/flat_bvh.h) at full precision, or the quantized BVH of
// the compact scene with -DMR_COMPACT=1 (traverse_compact.cl). Both are stack-based
// traversals that visit the nearer child first and skip subtrees beyond the closest hit.
// Cut-out materials (alpha mask/blend) reject hits as render/accel.cpp's Embree filter
// does, for closest and shadow rays alike, with the same hash of the ray.

#define STACK_SIZE 64         // kMaxBvhDepth on the host
#define LEAF_BIT 0x80000000u  // kLeafBit
#define LEAF_COUNT_BITS 4     // kLeafCountBits

// Slab test of the box lo..hi; `inv_dir` has no infinities (see safe_inverse). On a hit,
// *t_near is where the ray enters the box (clamped to the ray's range). The exit distance
// is scaled by 1 + 2 gamma(3), as render/compact_accel.cpp's (Ize, JCGT 2013), so a ray
// grazing a box corner is not lost to the rounding of the slab distances.
#define SLAB_SLACK (1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f))
bool box_hit(float3 lo_corner, float3 hi_corner, float3 org, float3 inv_dir, float tmin,
             float tmax, float* t_near) {
  const float3 t0 = (lo_corner - org) * inv_dir;
  const float3 t1 = (hi_corner - org) * inv_dir;
  // min/max, not fmin/fmax: no operand is NaN (finite boxes, origins and inverse
  // directions), and the NaN-aware versions cost a compare and blend each on a CPU.
  const float3 a = min(t0, t1), b = max(t0, t1);
  const float lo = max(max(a.x, a.y), max(a.z, tmin));
  const float hi = min(min(b.x, b.y) * SLAB_SLACK, min(b.z * SLAB_SLACK, tmax));
  *t_near = lo;
  return lo <= hi;
}

// 1 / dir with zero components replaced by a tiny value of the same sign, so the slab
// test never computes 0 * inf.
float3 safe_inverse(float3 d) {
  const float3 tiny = copysign((float3)(1e-30f), d);
  return 1.0f / select(d, tiny, isless(fabs(d), (float3)(1e-30f)));
}

// accel.cpp's alpha_filter: whether `ray` passes through scene triangle `prim` at
// barycentrics (u, v).
bool cut_out(const SceneData* sc, const Ray* ray, uint prim, float u, float v) {
  const __global MaterialRecord* m = &sc->materials[material_of(sc, prim)];
  if (m->alpha_mode == 0u) return false;
  const ShadingRecord d = scene_shading(sc, prim);
  const float key[6] = {ray->org.x, ray->org.y, ray->org.z, ray->dir.x, ray->dir.y, ray->dir.z};
  return passes_through(sc, m, shading_uv(&d, 1.0f - u - v, u, v), cutout_hash(key, prim));
}

// The shared ray/triangle test (render/shared/triangle.h) on scene triangle `prim` with
// corner v0 and edges e1n = v0 - v1 (Embree's e1) and e2 = v2 - v0. Updates `hit` and
// returns true for a hit in (tmin, *tmax) that is not cut out.
bool tri_hit(const SceneData* sc, uint prim, float3 v0, float3 e1n, float3 e2, const Ray* ray,
             float* tmax, Hit* hit) {
  float t, u, v;
  if (!intersect_triangle(ray->org, ray->dir, ray->tmin, *tmax, v0, e1n, e2, &t, &u, &v))
    return false;
  if (sc->cutouts && cut_out(sc, ray, prim, u, v)) return false;
  *tmax = t;
  hit->t = t;
  hit->prim = prim;
  hit->u = u;
  hit->v = v;
  hit->ng = triangle_normal(e1n, e2);  // as Embree's, zero signs included
  return true;
}

#ifndef MR_COMPACT

// Closest hit (any_hit = false) or any hit (any_hit = true, for shadow rays). `ref` is the
// child reference being visited (a node index or a leaf, see render/flat_bvh.h).
bool traverse(const SceneData* sc, const Ray* ray, bool any_hit, Hit* hit) {
  const __global FlatNode* nodes = sc->nodes;
  const __global FlatTriangle* tris = sc->tris;
  const float3 inv_dir = safe_inverse(ray->dir);
  float tmax = ray->tmax;
  uint stack[STACK_SIZE];
  float stack_t[STACK_SIZE];  // entry distance of each stacked subtree
  int sp = 0;
  uint ref = 0;  // the root node
  bool found = false;
  for (;;) {
    bool descend = false;
    if (ref & LEAF_BIT) {
      const uint first = (ref & ~LEAF_BIT) >> LEAF_COUNT_BITS;
      const uint count = (ref & ((1u << LEAF_COUNT_BITS) - 1u)) + 1u;
      for (uint i = first; i < first + count; ++i)
        if (tri_hit(sc, tris[i].prim, load3(tris[i].v0), load3(tris[i].e1n), load3(tris[i].e2),
                    ray, &tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    } else {
      const __global FlatNode* n = &nodes[ref];
      float t0, t1;
      const bool h0 = box_hit(load3(n->lo[0]), load3(n->hi[0]), ray->org, inv_dir, ray->tmin,
                              tmax, &t0);
      const bool h1 = box_hit(load3(n->lo[1]), load3(n->hi[1]), ray->org, inv_dir, ray->tmin,
                              tmax, &t1);
      if (h0 && h1) {
        const int first_child = t1 < t0 ? 1 : 0;
        stack[sp] = n->child[1 - first_child];
        stack_t[sp] = first_child ? t0 : t1;
        ++sp;
        ref = n->child[first_child];
        descend = true;
      } else if (h0 || h1) {
        ref = n->child[h0 ? 0 : 1];
        descend = true;
      }
    }
    if (descend) continue;
    // Pop the nearest pending subtree that can still hold a closer hit.
    for (;;) {
      if (sp == 0) return found;
      --sp;
      if (stack_t[sp] <= tmax) break;
    }
    ref = stack[sp];
  }
}

#endif  // MR_COMPACT
