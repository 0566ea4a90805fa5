// The ray tests every tree uses (the slab test, the shared triangle test with cut-outs),
// and the flat BVH (render/flat_bvh.h) as a tree for render/shared/bvh_walk.h's walk, at
// full precision; with -DMR_COMPACT=1 traverse_compact.cl's quantized tree replaces it.
// Cut-out materials (alpha mask/blend) reject hits as render/accel.cpp's Embree filter
// does, for closest and shadow rays alike, with the same hash of the ray.

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

// The tree render/shared/bvh_walk.h walks (its interface is described there). The flat
// BVH stores its children's boxes: a node carries no box down.
typedef char NodeBox;
typedef struct {
  uint child[2];
} NodeKids;

bool tree_root(const SceneData* sc, NodeBox* box) {
  *box = 0;
  return true;
}

int tree_children(const SceneData* sc, uint ref, NodeBox box, const Ray* ray, float3 inv_dir,
                  float tmax, float t[2], NodeKids* kids) {
  const __global FlatNode* n = &sc->nodes[ref];
  kids->child[0] = n->child[0], kids->child[1] = n->child[1];
  return (box_hit(load3(n->lo[0]), load3(n->hi[0]), ray->org, inv_dir, ray->tmin, tmax, &t[0])
              ? 1 : 0) |
         (box_hit(load3(n->lo[1]), load3(n->hi[1]), ray->org, inv_dir, ray->tmin, tmax, &t[1])
              ? 2 : 0);
}

uint tree_child(const SceneData* sc, const NodeKids* kids, int c, NodeBox* box) {
  *box = 0;
  return kids->child[c];
}

bool tree_leaf_hit(const SceneData* sc, uint slot, const Ray* ray, float* tmax, Hit* hit) {
  const __global FlatTriangle* tri = &sc->tris[slot];
  return tri_hit(sc, tri->prim, load3(tri->v0), load3(tri->e1n), load3(tri->e2), ray, tmax,
                 hit);
}

#endif  // MR_COMPACT
