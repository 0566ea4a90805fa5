#include "render/compact_kdtree.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/error.h"
#include "render/compact_kdtree_inner.h"
#include "render/shared/triangle.h"

namespace multiray {

namespace {

// A triangle's reference in a node under construction, with the bounds of the part of
// the triangle inside the node's cell.
struct Ref {
  uint32_t tri;
  Bounds3 box;
};

float area(const Bounds3& b) {
  const Vec3 e = b.extent();
  return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
}

Bounds3 intersection(const Bounds3& a, const Bounds3& b) {
  return Bounds3{max(a.lo, b.lo), min(a.hi, b.hi)};
}

// The nearest float at or below (at or above) `d`.
float round_down(double d) {
  const float f = float(d);
  return double(f) > d ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double d) {
  const float f = float(d);
  return double(f) < d ? std::nextafter(f, INFINITY) : f;
}

// Bounds of triangle `v` clipped to `cell` (Sutherland-Hodgman against the six planes, in
// double precision, rounded outwards), within the triangle's own bounds and the cell.
// Empty when nothing of the triangle is inside.
Bounds3 clipped_bounds(const Vec3 v[3], const Bounds3& cell) {
  struct P {
    double c[3];
  };
  P poly[2][12];  // a triangle cut by six planes has at most nine corners
  int n = 3, cur = 0;
  for (int k = 0; k < 3; ++k) poly[0][k] = P{{v[k].x, v[k].y, v[k].z}};
  for (int a = 0; a < 3 && n > 0; ++a)
    for (int side = 0; side < 2 && n > 0; ++side) {
      const double plane = side ? cell.hi[a] : cell.lo[a];
      // Signed distance inside the half-space: >= 0 keeps the point.
      const auto inside = [&](const P& p) { return side ? plane - p.c[a] : p.c[a] - plane; };
      const P* in = poly[cur];
      P* out = poly[1 - cur];
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const P& p = in[i];
        const P& q = in[(i + 1) % n];
        const double dp = inside(p), dq = inside(q);
        if (dp >= 0) out[m++] = p;
        if ((dp >= 0) != (dq >= 0)) {
          const double s = dp / (dp - dq);
          P x;
          for (int k = 0; k < 3; ++k) x.c[k] = p.c[k] + (q.c[k] - p.c[k]) * s;
          x.c[a] = plane;
          out[m++] = x;
        }
      }
      n = m, cur = 1 - cur;
    }
  if (n == 0) return Bounds3{};
  Bounds3 b;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min(b.lo[k], round_down(poly[cur][i].c[k]));
      b.hi[k] = std::max(b.hi[k], round_up(poly[cur][i].c[k]));
    }
  Bounds3 tri;
  for (int k = 0; k < 3; ++k) tri.extend(v[k]);
  return intersection(intersection(b, tri), cell);
}

class KdBuilder {
 public:
  KdBuilder(const CompactMesh& mesh, const KdBuildOptions& o, int max_depth, CompactKdTree& tree)
      : mesh_(mesh), o_(o), max_depth_(max_depth), tree_(tree) {}

  // Makes tree_.nodes[node] the root of a subtree over `refs` (consumed) in `cell`, below
  // `path_refs` inner references.
  void build(uint32_t node, const Bounds3& cell, std::vector<Ref>& refs, int depth,
             int path_refs) {
    tree_.depth = std::max(tree_.depth, depth);
    // Room for inner references here: the node's and the path's budgets.
    const int room = std::min(o_.inner_refs_max, o_.path_refs_max - path_refs);
    const Split s = int(refs.size()) <= o_.leaf_triangles || depth >= max_depth_
                        ? Split{}
                        : find_split(cell, refs, room > 0);
    if (s.axis < 0 || !(s.cost < o_.intersection_cost * float(refs.size()))) {
      make_leaf(node, refs);
      return;
    }
    const kd_inner::InnerPicker kept = pick_inner(cell, refs, s, room);
    Bounds3 lcell = cell, rcell = cell;
    lcell.hi[s.axis] = s.pos;
    rcell.lo[s.axis] = s.pos;
    std::vector<Ref> left, right;
    for (size_t i = 0; i < refs.size(); ++i) {
      const Ref& r = refs[i];
      const float b0 = r.box.lo[s.axis], b1 = r.box.hi[s.axis];
      if (kept.contains(uint32_t(i))) {
        continue;  // in this node's slot, not in the children
      } else if (b0 == s.pos && b1 == s.pos) {
        (s.planar_left ? left : right).push_back(r);
      } else if (b1 <= s.pos) {
        left.push_back(r);
      } else if (b0 >= s.pos) {
        right.push_back(r);
      } else {  // straddles: clipped again to each side
        Vec3 v[3];
        for (int k = 0; k < 3; ++k) v[k] = mesh_.corner(r.tri, k);
        for (int side = 0; side < 2; ++side) {
          const Bounds3& c = side ? rcell : lcell;
          Bounds3 b = clipped_bounds(v, c);
          // Rounding may clip away a sliver the bounds say is there: keep the reference.
          if (b.empty()) b = intersection(r.box, c);
          (side ? right : left).push_back(Ref{r.tri, b});
        }
      }
    }
    const uint32_t first = add_children(node, s, refs, kept);
    std::vector<Ref>().swap(refs);
    build(first, lcell, left, depth + 1, path_refs + kept.count());
    build(first + 1, rcell, right, depth + 1, path_refs + kept.count());
  }

 private:
  struct Split {
    int axis = -1;
    float pos = 0, cost = INFINITY;
    bool planar_left = false;
  };
  // Sorted by position, then ends before planar triangles before starts (Wald & Havran
  // §4.2), so that the counts at a plane are complete when it is evaluated.
  struct Event {
    float pos;
    int type;  // 0 end, 1 planar, 2 start
    bool operator<(const Event& e) const { return pos < e.pos || (pos == e.pos && type < e.type); }
  };

  // The straddlers of split `s` that the node keeps (none when `room` is 0).
  kd_inner::InnerPicker pick_inner(const Bounds3& cell, const std::vector<Ref>& refs,
                                   const Split& s, int room) const {
    kd_inner::InnerPicker picker(cell, planes_, o_.tau_occu, o_.tau_freq, room);
    if (room <= 0) return picker;
    for (size_t i = 0; i < refs.size(); ++i)
      if (refs[i].box.lo[s.axis] < s.pos && refs[i].box.hi[s.axis] > s.pos)
        picker.offer(uint32_t(i), refs[i].box);
    return picker;
  }

  // Appends the node's reference slot (when it keeps any) and its two children, and writes
  // the node; returns the lower child's index.
  uint32_t add_children(uint32_t node, const Split& s, const std::vector<Ref>& refs,
                        const kd_inner::InnerPicker& kept) {
    const bool slot = kept.count() > 0;
    const size_t first = tree_.nodes.size() + (slot ? 1 : 0);
    if (first + 1 > kMaxKdNode)
      throw DeviceError("kd-tree: more than 2^29 nodes (" + std::to_string(first) + ")");
    if (slot) {
      const uint32_t second = kept.count() > 1 ? refs[kept.picked(1)].tri : KdNode::kNoRef;
      tree_.nodes.push_back(KdNode{refs[kept.picked(0)].tri, second});
      ++tree_.slots;
      tree_.inner_refs += size_t(kept.count());
    }
    tree_.nodes.push_back(KdNode{});
    tree_.nodes.push_back(KdNode{});
    tree_.nodes[node] = KdNode{std::bit_cast<uint32_t>(s.pos),
                               uint32_t(first) << 3 | (slot ? 4u : 0u) | uint32_t(s.axis)};
    return uint32_t(first);
  }

  void make_leaf(uint32_t node, const std::vector<Ref>& refs) {
    const size_t first = tree_.refs.size();
    if (first + refs.size() > kMaxKdIndex)
      throw DeviceError("kd-tree: more than 2^30 triangle references");
    for (const Ref& r : refs) tree_.refs.push_back(r.tri);
    tree_.nodes[node] = KdNode{uint32_t(refs.size()), uint32_t(first) << 2 | KdNode::kLeaf};
  }

  // SAH cost of splitting `cell` at `pos` on `axis` with nl, nr triangles strictly on each
  // side and np in the plane, which go to the cheaper side.
  void consider(const Bounds3& cell, float cell_area, int axis, float pos, int nl, int nr, int np,
                Split& best) const {
    Bounds3 l = cell, r = cell;
    l.hi[axis] = pos;
    r.lo[axis] = pos;
    const float pl = area(l) / cell_area, pr = area(r) / cell_area;
    const auto cost = [&](int a, int b) {
      const float c = o_.traversal_cost + o_.intersection_cost * (pl * float(a) + pr * float(b));
      return a == 0 || b == 0 ? c * (1.0f - o_.empty_bonus) : c;
    };
    const float with_left = cost(nl + np, nr), with_right = cost(nl, nr + np);
    const bool left = with_left <= with_right;
    const float c = left ? with_left : with_right;
    if (c < best.cost) best = Split{axis, pos, c, left};
  }

  // With `planes`, also records the node's candidate planes in planes_ (for pick_inner).
  Split find_split(const Bounds3& cell, const std::vector<Ref>& refs, bool planes) {
    Split best;
    for (int a = 0; a < 3; ++a) planes_.clear(a);  // none from another node
    const float cell_area = area(cell);
    if (!(cell_area > 0)) return best;
    const int n = int(refs.size());
    for (int a = 0; a < 3; ++a) {
      if (!(cell.hi[a] > cell.lo[a])) continue;
      events_.clear();
      for (const Ref& r : refs) {
        if (r.box.lo[a] == r.box.hi[a]) {
          events_.push_back(Event{r.box.lo[a], 1});
        } else {
          events_.push_back(Event{r.box.lo[a], 2});
          events_.push_back(Event{r.box.hi[a], 0});
        }
      }
      std::sort(events_.begin(), events_.end());
      if (planes)
        for (const Event& e : events_) planes_.add(a, e.pos, cell);
      int nl = 0, nr = n;
      for (size_t i = 0; i < events_.size();) {
        const float pos = events_[i].pos;
        int ends = 0, planar = 0, starts = 0;
        for (; i < events_.size() && events_[i].pos == pos && events_[i].type == 0; ++i) ++ends;
        for (; i < events_.size() && events_[i].pos == pos && events_[i].type == 1; ++i) ++planar;
        for (; i < events_.size() && events_[i].pos == pos && events_[i].type == 2; ++i) ++starts;
        nr -= planar + ends;
        if (pos > cell.lo[a] && pos < cell.hi[a])
          consider(cell, cell_area, a, pos, nl, nr, planar, best);
        nl += starts + planar;
      }
    }
    return best;
  }

  const CompactMesh& mesh_;
  const KdBuildOptions& o_;
  const int max_depth_;
  CompactKdTree& tree_;
  std::vector<Event> events_;
  kd_inner::CandidatePlanes planes_;  // of the node being split (overwritten below it)
};

// The shared ray/triangle test (render/shared/triangle.h) on the decoded triangle, with
// compact_accel.cpp's edges (e1n = v0 - v1, e2 = v2 - v0), so that both structures report
// the same t, barycentrics and normal.
bool triangle_hit(const CompactMesh& m, uint32_t prim, const Ray& ray, float& tmax, Hit& hit) {
  const Vec3 v0 = m.corner(prim, 0), e1n = v0 - m.corner(prim, 1), e2 = m.corner(prim, 2) - v0;
  float t, u, v;
  if (!intersect_triangle(ray.org, ray.dir, ray.tmin, tmax, v0, e1n, e2, &t, &u, &v)) return false;
  tmax = t;
  hit.t = t, hit.prim = prim, hit.u = u, hit.v = v;
  hit.ng = triangle_normal(e1n, e2);
  return true;
}

// Two kinds of rounding could make a ray skip a cell that references the triangle it
// hits: the Moller-Trumbore test accepts points up to a few ulps outside a triangle (seen
// at vertices: a hit 3 ulps above a triangle's top plane, in the cell above it, which
// does not reference it), and the distances where the ray crosses planes are a few ulps
// off. So each split plane is a slab of half-width CompactKdTree::pad, whose cells on
// both sides the ray enters, and cell intervals are compared with this relative slack
// (after Ize, "Robust BVH ray traversal", JCGT 2013, which widens box exits likewise).
constexpr float kSlack = 4.0f * FLT_EPSILON;

float widen(float t) { return t + std::fabs(t) * kSlack; }

bool traverse(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray, bool any_hit,
              Hit& hit) {
  if (tree.nodes.empty()) return false;
  const Vec3 inv = safe_inverse(ray.dir);
  // The ray's interval inside the (padded) root box.
  float t_near = -INFINITY, t_far = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float t0 = (tree.root.lo[a] - tree.pad - ray.org[a]) * inv[a];
    const float t1 = (tree.root.hi[a] + tree.pad - ray.org[a]) * inv[a];
    t_near = std::max(t_near, std::min(t0, t1));
    t_far = std::min(t_far, std::max(t0, t1));
  }
  t_near = std::max(ray.tmin, t_near - std::fabs(t_near) * kSlack);
  t_far = std::min(ray.tmax, widen(t_far));
  if (!(t_near <= t_far)) return false;
  struct Entry {
    uint32_t node;
    float t_near, t_far;
  };
  Entry stack[kMaxKdDepth];
  int sp = 0;
  float tmax = ray.tmax;
  bool found = false;
  uint32_t node = 0;
  for (;;) {
    const KdNode n = tree.nodes[node];
    if (!n.leaf()) {
      // The node's own triangles, tested whatever the ray does below.
      if (n.has_refs()) {
        const KdNode slot = tree.nodes[n.children() - 1];
        bool hit_here = triangle_hit(mesh, slot.first_ref(), ray, tmax, hit);
        if (slot.second_ref() != KdNode::kNoRef)
          hit_here |= triangle_hit(mesh, slot.second_ref(), ray, tmax, hit);
        found |= hit_here;
        if (any_hit && found) return true;
      }
      const int a = n.axis();
      const float split = n.split(), org = ray.org[a], ia = inv[a];
      const float t_lo = (split - tree.pad - org) * ia, t_hi = (split + tree.pad - org) * ia;
      // Along +a the ray is in the lower cell until t_hi and in the upper from t_lo; along
      // -a in the upper until t_lo and in the lower from t_hi.
      const bool up = ia >= 0.0f;
      const uint32_t first = n.children() + (up ? 0 : 1), second = n.children() + (up ? 1 : 0);
      const float first_exit = std::min(t_far, up ? t_hi : t_lo);
      const float second_entry = std::max(t_near, up ? t_lo : t_hi);
      // A hit on the node's own triangles may end the ray before its cell: then nothing
      // below is nearer (the test the stack's entries get below).
      const bool reached = t_near - std::fabs(t_near) * kSlack <= tmax;
      const bool go_first = reached && t_near <= widen(first_exit);
      const bool go_second = reached && second_entry <= widen(t_far);
      if (go_first && go_second) stack[sp++] = Entry{second, second_entry, t_far};
      if (go_first) {
        node = first, t_far = first_exit;
        continue;
      }
      if (go_second) {
        node = second, t_near = second_entry;
        continue;
      }
    } else {
      const uint32_t* refs = tree.refs.data() + n.index();
      for (uint32_t i = 0; i < n.count(); ++i)
        if (triangle_hit(mesh, refs[i], ray, tmax, hit)) {
          found = true;
          if (any_hit) return true;
        }
    }
    // The next pending cell that the ray enters before its closest hit so far. (Near the
    // top of the stack the slabs can put a farther cell above a nearer one.)
    for (;;) {
      if (sp == 0) return found;
      --sp;
      if (stack[sp].t_near - std::fabs(stack[sp].t_near) * kSlack <= tmax) break;
    }
    node = stack[sp].node, t_near = stack[sp].t_near, t_far = stack[sp].t_far;
  }
}

}  // namespace

CompactKdTree build_compact_kdtree(const CompactMesh& mesh, const KdBuildOptions& options) {
  if (options.inner_refs_max < 0 || options.inner_refs_max > kMaxKdInnerRefs)
    throw std::invalid_argument("kd-tree: inner_refs_max must be 0.." +
                                std::to_string(kMaxKdInnerRefs));
  CompactKdTree tree;
  const size_t triangles = mesh.indices.size() / 3;
  std::vector<Ref> refs;
  refs.reserve(triangles);
  for (size_t t = 0; t < triangles; ++t) {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) b.extend(mesh.corner(uint32_t(t), k));
    if (!is_finite(b.lo) || !is_finite(b.hi)) continue;  // cannot be hit
    tree.root.extend(b.lo), tree.root.extend(b.hi);
    refs.push_back(Ref{uint32_t(t), b});
  }
  if (refs.empty()) return tree;
  float largest = 0;  // coordinate magnitude
  for (int a = 0; a < 3; ++a)
    largest = std::max({largest, std::fabs(tree.root.lo[a]), std::fabs(tree.root.hi[a])});
  tree.pad = 16.0f * FLT_EPSILON * largest;
  const int max_depth =
      options.max_depth > 0
          ? std::min(options.max_depth, kMaxKdDepth)
          : std::min(kMaxKdDepth, int(8.0 + 1.3 * std::log2(double(refs.size()))));
  KdBuilder builder(mesh, options, max_depth, tree);
  tree.nodes.push_back(KdNode{});
  builder.build(0, tree.root, refs, 0, 0);
  return tree;
}

bool kdtree_intersect(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray,
                      Hit& hit) {
  return traverse(tree, mesh, ray, false, hit);
}

bool kdtree_occluded(const CompactKdTree& tree, const CompactMesh& mesh, const Ray& ray) {
  Hit unused;
  return traverse(tree, mesh, ray, true, unused);
}

}  // namespace multiray
