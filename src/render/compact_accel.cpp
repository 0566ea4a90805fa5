#include "render/compact_accel.h"

#include <algorithm>
#include <cmath>

#include "render/flat_bvh.h"
#include "render/shared/triangle.h"
#include "render/surface.h"

namespace multiray {

namespace {

// 1 + 2·gamma(3), gamma(n) = n·u / (1 - n·u), u = 2^-24 (see box_hit).
constexpr float kSlabSlack = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// Slab test; on a hit, *t_near is where the ray enters the box (within the ray's range).
// The exit distance is scaled by 1 + 2·gamma(3) (Ize, "Robust BVH ray traversal", JCGT
// 2013; pbrt's Bounds3::IntersectP): the rounding of the three slab distances can
// otherwise put a ray that grazes the box's corner or edge out by an ulp and lose a hit on
// a triangle lying in the box's face (the compact kd-tree's test found such misses at the
// Cornell box's corners).
bool box_hit(const Bounds3& b, Vec3 org, Vec3 inv, float tmin, float tmax, float* t_near) {
  const float tx0 = (b.lo.x - org.x) * inv.x, tx1 = (b.hi.x - org.x) * inv.x;
  const float ty0 = (b.lo.y - org.y) * inv.y, ty1 = (b.hi.y - org.y) * inv.y;
  const float tz0 = (b.lo.z - org.z) * inv.z, tz1 = (b.hi.z - org.z) * inv.z;
  const float lo = std::max(std::max(std::min(tx0, tx1), std::min(ty0, ty1)),
                            std::max(std::min(tz0, tz1), tmin));
  const float hi = std::min(std::min(std::max(tx0, tx1), std::max(ty0, ty1)) * kSlabSlack,
                            std::min(std::max(tz0, tz1) * kSlabSlack, tmax));
  *t_near = lo;
  return lo <= hi;
}

Bounds3 child_box(const CompactNode& n, int c, const Bounds3& parent) {
  Bounds3 b;
  b.lo = Vec3(dequantize_plane(parent.lo.x, parent.hi.x, n.lo[c][0]),
              dequantize_plane(parent.lo.y, parent.hi.y, n.lo[c][1]),
              dequantize_plane(parent.lo.z, parent.hi.z, n.lo[c][2]));
  b.hi = Vec3(dequantize_plane(parent.lo.x, parent.hi.x, n.hi[c][0]),
              dequantize_plane(parent.lo.y, parent.hi.y, n.hi[c][1]),
              dequantize_plane(parent.lo.z, parent.hi.z, n.hi[c][2]));
  return b;
}

bool cut_out(const CompactMesh& m, const Scene& scene, const Ray& ray, uint32_t prim, float u,
             float v) {
  const Material& mat = scene.materials[m.material(prim)];
  if (!mat.may_be_transparent()) return false;
  Vec2 uv{};
  if (!m.uvs.empty()) {
    const Vec2 a = m.uv(prim, 0), b = m.uv(prim, 1), c = m.uv(prim, 2);
    const float w = 1.0f - u - v;
    uv = Vec2{a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v};
  }
  return passes_through(scene, mat, uv, cutout_hash(ray, prim));
}

// The shared ray/triangle test (render/shared/triangle.h) on the decoded triangle, with
// the edges of the flat BVH's triangles (flat_bvh.h: e1n = v0 - v1, e2 = v2 - v0) so the
// normal is Embree's.
bool triangle_hit(const CompactMesh& m, const Scene* cutouts, uint32_t prim, const Ray& ray,
                  float& tmax, Hit& hit) {
  const Vec3 v0 = m.corner(prim, 0), e1n = v0 - m.corner(prim, 1), e2 = m.corner(prim, 2) - v0;
  float t, u, v;
  if (!intersect_triangle(ray.org, ray.dir, ray.tmin, tmax, v0, e1n, e2, &t, &u, &v)) return false;
  if (cutouts && cut_out(m, *cutouts, ray, prim, u, v)) return false;
  tmax = t;
  hit.t = t, hit.prim = prim, hit.u = u, hit.v = v;
  hit.ng = triangle_normal(e1n, e2);
  return true;
}

struct StackEntry {
  uint32_t ref;
  float t;      // where the ray enters the subtree
  Bounds3 box;  // the subtree root's decoded box (unused for leaves)
};

bool traverse(const CompactScene& c, const Scene* cutouts, const Ray& ray, bool any_hit,
              Hit& hit) {
  if (c.bvh.nodes.empty()) return false;
  const Vec3 inv = safe_inverse(ray.dir);
  float tmax = ray.tmax;
  StackEntry stack[kMaxBvhDepth];
  int sp = 0;
  uint32_t ref = 0;
  Bounds3 box = c.bvh.root;
  bool found = false;
  for (;;) {
    bool descend = false;
    if (ref & kLeafBit) {
      const uint32_t first = (ref & ~kLeafBit) >> kLeafCountBits;
      const uint32_t count = (ref & (kMaxLeafTriangles - 1)) + 1;
      for (uint32_t i = first; i < first + count; ++i)
        if (triangle_hit(c.mesh, cutouts, c.bvh.prims[i], ray, tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    } else {
      const CompactNode& n = c.bvh.nodes[ref];
      const Bounds3 b0 = child_box(n, 0, box), b1 = child_box(n, 1, box);
      float t0, t1;
      const bool h0 = box_hit(b0, ray.org, inv, ray.tmin, tmax, &t0);
      const bool h1 = box_hit(b1, ray.org, inv, ray.tmin, tmax, &t1);
      if (h0 && h1) {
        const int first = t1 < t0 ? 1 : 0;
        stack[sp++] = StackEntry{n.child[1 - first], first ? t0 : t1, first ? b0 : b1};
        ref = n.child[first], box = first ? b1 : b0;
        descend = true;
      } else if (h0 || h1) {
        ref = n.child[h0 ? 0 : 1], box = h0 ? b0 : b1;
        descend = true;
      }
    }
    if (descend) continue;
    for (;;) {  // the nearest pending subtree that can still hold a closer hit
      if (sp == 0) return found;
      --sp;
      if (stack[sp].t <= tmax) break;
    }
    ref = stack[sp].ref, box = stack[sp].box;
  }
}

}  // namespace

bool compact_intersect(const CompactScene& c, const Scene* cutouts, const Ray& ray, Hit& hit) {
  return traverse(c, cutouts, ray, false, hit);
}

bool compact_occluded(const CompactScene& c, const Scene* cutouts, const Ray& ray) {
  Hit unused;
  return traverse(c, cutouts, ray, true, unused);
}

}  // namespace multiray
