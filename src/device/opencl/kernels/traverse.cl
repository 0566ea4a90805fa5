// Ray queries against the flat BVH (device/opencl/bvh_flatten.h): a stack-based
// traversal that visits the nearer child first and skips subtrees beyond the closest hit.

#define STACK_SIZE 64  // kMaxBvhDepth on the host

// Slab test; `inv_dir` has no infinities (see safe_inverse). On a hit, *t_near is where
// the ray enters the box (clamped to the ray's range).
bool box_hit(const __global Node* n, float3 org, float3 inv_dir, float tmin, float tmax,
             float* t_near) {
  const float3 t0 = (load3(n->lo) - org) * inv_dir;
  const float3 t1 = (load3(n->hi) - org) * inv_dir;
  const float3 a = fmin(t0, t1), b = fmax(t0, t1);
  const float lo = fmax(fmax(a.x, a.y), fmax(a.z, tmin));
  const float hi = fmin(fmin(b.x, b.y), fmin(b.z, tmax));
  *t_near = lo;
  return lo <= hi;
}

// 1 / dir with zero components replaced by a tiny value of the same sign, so the slab
// test never computes 0 * inf.
float3 safe_inverse(float3 d) {
  const float3 tiny = copysign((float3)(1e-30f), d);
  return 1.0f / select(d, tiny, isless(fabs(d), (float3)(1e-30f)));
}

// Moller-Trumbore. Updates `hit` and returns true for a hit in (tmin, *tmax).
bool tri_hit(const __global Tri* tri, const Ray* ray, float* tmax, Hit* hit) {
  const float3 e1 = load3(tri->e1), e2 = load3(tri->e2);
  const float3 p = cross3(ray->dir, e2);
  const float det = dot3(e1, p);
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const float3 s = ray->org - load3(tri->v0);
  const float u = dot3(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const float3 q = cross3(s, e1);
  const float v = dot3(ray->dir, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  const float t = dot3(e2, q) * inv;
  if (!(t > ray->tmin && t < *tmax)) return false;
  *tmax = t;
  hit->t = t;
  hit->prim = tri->prim;
  hit->u = u;
  hit->v = v;
  hit->ng = cross3(e1, e2);
  return true;
}

// Closest hit (any_hit = false) or any hit (any_hit = true, for shadow rays).
bool traverse(const __global Node* nodes, const __global Tri* tris, const Ray* ray, bool any_hit,
              Hit* hit) {
  const float3 inv_dir = safe_inverse(ray->dir);
  float tmax = ray->tmax, t_near;
  if (!box_hit(&nodes[0], ray->org, inv_dir, ray->tmin, tmax, &t_near)) return false;
  uint stack[STACK_SIZE];
  float stack_t[STACK_SIZE];  // entry distance of each stacked subtree
  int sp = 0;
  uint node = 0;
  bool found = false;
  for (;;) {
    const __global Node* n = &nodes[node];
    bool descend = false;
    if (n->count > 0) {
      for (uint i = 0; i < n->count; ++i)
        if (tri_hit(&tris[n->offset + i], ray, &tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    } else {
      const uint left = node + 1, right = n->offset;
      float tl, tr;
      const bool hl = box_hit(&nodes[left], ray->org, inv_dir, ray->tmin, tmax, &tl);
      const bool hr = box_hit(&nodes[right], ray->org, inv_dir, ray->tmin, tmax, &tr);
      if (hl && hr) {
        const bool right_first = tr < tl;
        stack[sp] = right_first ? left : right;
        stack_t[sp] = right_first ? tl : tr;
        ++sp;
        node = right_first ? right : left;
        descend = true;
      } else if (hl || hr) {
        node = hl ? left : right;
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
    node = stack[sp];
  }
}

bool intersect_closest(const __global Node* nodes, const __global Tri* tris, const Ray* ray,
                       Hit* hit) {
  return traverse(nodes, tris, ray, false, hit);
}

bool occluded(const __global Node* nodes, const __global Tri* tris, const Ray* ray) {
  Hit unused;
  return traverse(nodes, tris, ray, true, &unused);
}
