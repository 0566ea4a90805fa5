#include "render/compact_accel.h"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <cstring>
#include <utility>
#include <vector>

#include "render/flat_bvh.h"
#include "render/shared/bvh_walk.h"
#include "render/shared/triangle.h"
#include "render/surface.h"

namespace multiray {

namespace {

// 1 + 2·gamma(3), gamma(n) = n·u / (1 - n·u), u = 2^-24 (see box_hit).
constexpr float kSlabSlack = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// Both children of a node, plane by plane, one vector an axis: lane 0 holds child 0's
// lower plane, lane 1 child 1's lower, lane 2 child 0's upper, lane 3 child 1's upper.
// GCC/Clang vector extensions: SSE on x86-64, NEON on ARM, plain code elsewhere.
typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));
typedef uint8_t v4u8 __attribute__((vector_size(4)));
struct ChildPlanes {
  v4f x, y, z;
};

v4f splat(float f) { return v4f{f, f, f, f}; }
// std::min and std::max lane by lane, NaNs included (std::min(a, b) is b < a ? b : a).
v4f vmin(v4f a, v4f b) { return b < a ? b : a; }
v4f vmax(v4f a, v4f b) { return a < b ? b : a; }
// Lanes of x (0-3) and y (4-7), as the indices say: one shufps with SSE.
template <int a, int b, int c, int d>
v4f shuffle(v4f x, v4f y) {
#if defined(__clang__)
  return __builtin_shufflevector(x, y, a, b, c, d);
#else
  return __builtin_shuffle(x, y, v4i{a, b, c, d});
#endif
}
v4f swap_halves(v4f v) { return shuffle<2, 3, 0, 1>(v, v); }

// The slab test of both children at once: bit c of the result is set when the ray meets
// child c within its range, and t_near[c] is where it enters. Lane for lane the arithmetic
// of the scalar test it replaced (so the same boxes are hit): the exit distance is scaled
// by 1 + 2·gamma(3) (Ize, "Robust BVH ray traversal", JCGT 2013; pbrt's
// Bounds3::IntersectP), since the rounding of the three slab distances can otherwise put
// a ray that grazes a box's corner or edge out by an ulp and lose a hit on a triangle
// lying in the box's face (the compact kd-tree's test found such misses at the Cornell
// box's corners).
[[gnu::always_inline]] inline int two_box_hit(const ChildPlanes& p, Vec3 org, Vec3 inv, float tmin,
                                              float tmax, float t_near[2]) {
  const v4f tx = (p.x - org.x) * inv.x, ty = (p.y - org.y) * inv.y, tz = (p.z - org.z) * inv.z;
  const v4f sx = swap_halves(tx), sy = swap_halves(ty), sz = swap_halves(tz);
  const v4f lo = vmax(vmax(vmin(tx, sx), vmin(ty, sy)), vmax(vmin(tz, sz), splat(tmin)));
  const v4f hi = vmin(vmin(vmax(tx, sx), vmax(ty, sy)) * kSlabSlack,
                      vmin(vmax(tz, sz) * kSlabSlack, splat(tmax)));
  t_near[0] = lo[0], t_near[1] = lo[1];
  return (lo[0] <= hi[0] ? 1 : 0) | (lo[1] <= hi[1] ? 2 : 0);
}

// A node's own box as the quantized traversal carries it down and keeps it on its stack:
// x, y, z in lanes 0-2 of two registers, so that neither taking a child's box out of the
// decoded planes nor spreading it for the next decode goes through memory.
struct LaneBox {
  v4f lo, hi;
};

// One axis of both children decoded from the parent's box: 8-bit codes `q` in the lanes'
// order, render/shared/compact.h's arithmetic lane for lane: the lower planes (lanes 0,
// 1) lo + (hi - lo) * q / 255, the upper ones (lanes 2, 3) hi + (lo - hi) * (255 - q) /
// 255. No select: each is exact at its own end.
template <int a>
v4f dequantize_axis(const LaneBox& box, v4i q) {
  const v4f base = shuffle<a, a, 4 + a, 4 + a>(box.lo, box.hi);   // lo lo hi hi
  const v4f other = shuffle<4 + a, 4 + a, a, a>(box.lo, box.hi);  // hi hi lo lo
  const v4f w = __builtin_convertvector(q ^ v4i{0, 0, 255, 255}, v4f) * (1.0f / 255.0f);
  return base + (other - base) * w;
}

// The node stores its codes in the lanes' order: with SSE2, one 16-byte load (the codes
// and the first child reference; a node is 20 bytes) widened by unpacking with zeros.
ChildPlanes decode_children(const CompactNode& n, const LaneBox& parent) {
  v4i qx, qy, qz;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&n));
  const __m128i lo16 = _mm_unpacklo_epi8(bytes, zero), hi16 = _mm_unpackhi_epi8(bytes, zero);
  qx = (v4i)_mm_unpacklo_epi16(lo16, zero);
  qy = (v4i)_mm_unpackhi_epi16(lo16, zero);
  qz = (v4i)_mm_unpacklo_epi16(hi16, zero);
#else
  const auto axis = [&](int a) {
    v4u8 q;
    std::memcpy(&q, n.q[a], sizeof(q));
    return __builtin_convertvector(q, v4i);
  };
  qx = axis(0), qy = axis(1), qz = axis(2);
#endif
  return ChildPlanes{dequantize_axis<0>(parent, qx), dequantize_axis<1>(parent, qy),
                     dequantize_axis<2>(parent, qz)};
}

// Child c's box out of its planes: lane c of each axis is its lower plane, lane c + 2 its
// upper one.
LaneBox child_box(const ChildPlanes& p, int c) {
  const v4f xy_lo = shuffle<0, 4, 1, 5>(p.x, p.y);  // x0 y0 x1 y1
  const v4f xy_hi = shuffle<2, 6, 3, 7>(p.x, p.y);  // x2 y2 x3 y3
  if (c == 0) return LaneBox{shuffle<0, 1, 4, 4>(xy_lo, p.z), shuffle<0, 1, 6, 6>(xy_hi, p.z)};
  return LaneBox{shuffle<2, 3, 5, 5>(xy_lo, p.z), shuffle<2, 3, 7, 7>(xy_hi, p.z)};
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

// The shared ray/triangle test (render/shared/triangle.h) on a decoded triangle given as
// the flat BVH's edges (flat_bvh.h: e1n = v0 - v1, e2 = v2 - v0), so the normal is Embree's.
bool triangle_hit(const CompactMesh& m, const Scene* cutouts, uint32_t prim, Vec3 v0, Vec3 e1n,
                  Vec3 e2, const Ray& ray, float& tmax, Hit& hit) {
  float t, u, v;
  if (!intersect_triangle(ray.org, ray.dir, ray.tmin, tmax, v0, e1n, e2, &t, &u, &v)) return false;
  if (cutouts && cut_out(m, *cutouts, ray, prim, u, v)) return false;
  tmax = t;
  hit.t = t, hit.prim = prim, hit.u = u, hit.v = v;
  hit.ng = triangle_normal(e1n, e2);
  return true;
}

static_assert(MR_LEAF_BIT == kLeafBit && MR_LEAF_COUNT_BITS == kLeafCountBits &&
              MR_BVH_STACK == kMaxBvhDepth);

// A node's children as the walk (render/shared/bvh_walk.h) keeps them between testing
// them and taking one: their decoded planes and their references.
struct NodeKids {
  ChildPlanes planes;
  const uint32_t* refs;
};

// The compact tree as stored: a node's child boxes are decoded from its own box (which
// the walk carries down and keeps on its stack), a triangle from the quantized mesh at
// each test.
struct QuantizedTree {
  const CompactScene& c;
  const Scene* cutouts;
  using Box = LaneBox;
  using Kids = NodeKids;
  Box root() const {
    const Bounds3& r = c.bvh.root;
    return Box{v4f{r.lo.x, r.lo.y, r.lo.z, 0.0f}, v4f{r.hi.x, r.hi.y, r.hi.z, 0.0f}};
  }
  void triangle(uint32_t prim, Vec3& v0, Vec3& e1n, Vec3& e2) const {
    v0 = c.mesh.corner(prim, 0), e1n = v0 - c.mesh.corner(prim, 1);
    e2 = c.mesh.corner(prim, 2) - v0;
  }
};

// The same tree decoded once into floats: nothing to carry down. Triangles from the
// textbook indexed mesh (`per_slot` false: reference, three 32-bit vertex indices, float
// positions, as Seo et al.'s uncompressed tree) or stored by leaf slot, edges ready.
template <bool per_slot>
struct FloatTree {
  const CompactFloatTree& t;
  const CompactScene& c;
  const Scene* cutouts;
  struct Box {};
  using Kids = NodeKids;
};

// The walk's tree interface (render/shared/bvh_walk.h) for both.
bool tree_root(const QuantizedTree* q, LaneBox* box) {
  *box = q->root();
  return !q->c.bvh.nodes.empty();
}
template <bool per_slot>
bool tree_root(const FloatTree<per_slot>* f, typename FloatTree<per_slot>::Box*) {
  return !f->t.nodes.empty();
}

int tree_children(const QuantizedTree* q, uint32_t ref, const LaneBox& box, const Ray* ray,
                  Vec3 inv, float tmax, float t[2], NodeKids* kids) {
  const CompactNode& n = q->c.bvh.nodes[ref];
  *kids = NodeKids{decode_children(n, box), n.child};
  return two_box_hit(kids->planes, ray->org, inv, ray->tmin, tmax, t);
}
template <bool per_slot>
int tree_children(const FloatTree<per_slot>* f, uint32_t ref, typename FloatTree<per_slot>::Box,
                  const Ray* ray, Vec3 inv, float tmax, float t[2], NodeKids* kids) {
  const auto& n = f->t.nodes[ref];
  std::memcpy(&kids->planes, n.planes, sizeof(kids->planes));
  kids->refs = n.child;
  return two_box_hit(kids->planes, ray->org, inv, ray->tmin, tmax, t);
}

uint32_t tree_child(const QuantizedTree*, const NodeKids* kids, int c, LaneBox* box) {
  *box = child_box(kids->planes, c);
  return kids->refs[c];
}
template <bool per_slot>
uint32_t tree_child(const FloatTree<per_slot>*, const NodeKids* kids, int c,
                    typename FloatTree<per_slot>::Box*) {
  return kids->refs[c];
}

bool tree_leaf_hit(const QuantizedTree* q, uint32_t slot, const Ray* ray, float* tmax, Hit* hit) {
  const uint32_t prim = q->c.bvh.prims[slot];
  Vec3 v0, e1n, e2;
  q->triangle(prim, v0, e1n, e2);
  return triangle_hit(q->c.mesh, q->cutouts, prim, v0, e1n, e2, *ray, *tmax, *hit);
}
template <bool per_slot>
bool tree_leaf_hit(const FloatTree<per_slot>* f, uint32_t slot, const Ray* ray, float* tmax,
                   Hit* hit) {
  const uint32_t prim = f->t.prims[slot];
  Vec3 v0, e1n, e2;
  if (per_slot) {
    const Vec3* tri = &f->t.triangles[3 * size_t(slot)];
    v0 = tri[0], e1n = tri[1], e2 = tri[2];
  } else {
    const uint32_t* face = &f->t.faces[3 * size_t(prim)];
    v0 = f->t.positions[face[0]], e1n = v0 - f->t.positions[face[1]];
    e2 = f->t.positions[face[2]] - v0;
  }
  return triangle_hit(f->c.mesh, f->cutouts, prim, v0, e1n, e2, *ray, *tmax, *hit);
}

}  // namespace

bool compact_intersect(const CompactScene& c, const Scene* cutouts, const Ray& ray, Hit& hit) {
  const QuantizedTree tree{c, cutouts};
  return bvh_walk(&tree, &ray, false, &hit);
}

bool compact_occluded(const CompactScene& c, const Scene* cutouts, const Ray& ray) {
  const QuantizedTree tree{c, cutouts};
  Hit unused;
  return bvh_walk(&tree, &ray, true, &unused);
}

CompactFloatTree decode_compact_tree(const CompactScene& c) {
  CompactFloatTree t;
  t.nodes.resize(c.bvh.nodes.size());
  std::vector<std::pair<uint32_t, LaneBox>> todo;  // inner nodes and their boxes
  if (!c.bvh.nodes.empty()) todo.push_back({0u, QuantizedTree{c, nullptr}.root()});
  while (!todo.empty()) {
    const auto [ref, box] = todo.back();
    todo.pop_back();
    const CompactNode& n = c.bvh.nodes[ref];
    const ChildPlanes p = decode_children(n, box);
    std::memcpy(t.nodes[ref].planes, &p, sizeof(p));
    for (int k = 0; k < 2; ++k) {
      t.nodes[ref].child[k] = n.child[k];
      if (!(n.child[k] & kLeafBit)) todo.push_back({n.child[k], child_box(p, k)});
    }
  }
  t.prims = c.bvh.prims.unpacked();
  t.positions.resize(c.mesh.positions.size());
  for (uint32_t v = 0; v < t.positions.size(); ++v) t.positions[v] = c.mesh.position(v);
  t.faces.resize(c.mesh.indices.size());
  for (size_t i = 0; i < t.faces.size(); ++i) t.faces[i] = c.mesh.indices[i];
  t.triangles.reserve(3 * t.prims.size());
  for (uint32_t slot = 0; slot < t.prims.size(); ++slot) {
    Vec3 v0, e1n, e2;
    QuantizedTree{c, nullptr}.triangle(t.prims[slot], v0, e1n, e2);
    t.triangles.insert(t.triangles.end(), {v0, e1n, e2});
  }
  return t;
}

bool compact_float_intersect(const CompactFloatTree& t, const CompactScene& c,
                             const Scene* cutouts, const Ray& ray, Hit& hit, bool per_slot) {
  if (per_slot) {
    const FloatTree<true> tree{t, c, cutouts};
    return bvh_walk(&tree, &ray, false, &hit);
  }
  const FloatTree<false> tree{t, c, cutouts};
  return bvh_walk(&tree, &ray, false, &hit);
}

}  // namespace multiray
