// The compact kd-tree (render/compact_kdtree.h), in both forms (leaf-only and Choi et
// al.'s, with triangles in inner nodes), against the compact BVH's traversal
// (compact_accel.h) on the same decoded triangles: the same closest hits and the same
// occlusion answers over random rays, a well-formed tree, and degenerate scenes. The
// Choi form's budgets and measures: compact_kdtree_inner_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "kdtree_walk.h"
#include "render/compact_accel.h"
#include "render/compact_kdtree.h"
#include "scene/builders.h"

namespace multiray {
namespace compact_kdtree_test {

// Boxes turned about y, spheres of several sizes (one inside a box, one crossing a wall)
// and a quad laid twice on the floor (coplanar triangles: ties), in a Cornell box.
Scene cluttered_scene() {
  Scene s = make_cornell_box();
  const uint32_t m = s.material_ids.front();
  add_box(s, Vec3(0.3f, 0.2f, 0.1f), Vec3(0.15f, 0.2f, 0.1f), 33.0f, m);
  add_box(s, Vec3(-0.4f, 0.5f, -0.2f), Vec3(0.2f, 0.05f, 0.3f), -12.0f, m);
  add_sphere(s, Vec3(0.3f, 0.2f, 0.1f), 0.12f, 12, 24, false, m);
  add_sphere(s, Vec3(-0.9f, 1.0f, 0.0f), 0.3f, 16, 32, false, m);
  add_sphere(s, Vec3(0.0f, 1.2f, 0.3f), 0.02f, 6, 12, true, m);
  for (int k = 0; k < 2; ++k)
    add_quad(s, Vec3(-0.5f, 0.001f, 0.5f), Vec3(0.5f, 0.001f, 0.5f), Vec3(0.5f, 0.001f, -0.5f),
             Vec3(-0.5f, 0.001f, -0.5f), m);
  s.name = "cluttered";
  return s;
}

// Rays of four kinds: from around the scene towards its vertices, from inside in random
// directions, from inside along the axes and diagonals (direction components of zero),
// and segments between two inside points (tmin > 0, finite tmax, as shadow rays).
std::vector<Ray> random_rays(const Scene& s, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  const Bounds3 b = s.bounds();
  const float r = length(b.extent());
  const auto inside = [&] { return b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent(); };
  const auto direction = [&] {
    Vec3 d;
    do d = Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
    while (length(d) < 0.01f);
    return normalize(d);
  };
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    switch (i % 4) {
      case 0: {
        const Vec3 target = s.positions[rng() % s.positions.size()];
        const Vec3 org = b.center() + direction() * r;
        rays.push_back(Ray{org, normalize(target - org), 0.0f, INFINITY});
        break;
      }
      case 1:
        rays.push_back(Ray{inside(), direction(), 0.0f, INFINITY});
        break;
      case 2: {
        Vec3 d;
        for (int k = 0; k < 3; ++k) d[k] = float(int(rng() % 3) - 1);
        if (d.x == 0 && d.y == 0 && d.z == 0) d.y = -1;
        rays.push_back(Ray{inside(), normalize(d), 0.0f, INFINITY});
        break;
      }
      default: {
        const Vec3 a = inside(), c = inside();
        const float len = length(c - a);
        if (!(len > 0)) continue;
        rays.push_back(Ray{a, (c - a) / len, 1e-4f * r, len});
      }
    }
  }
  return rays;
}

struct Agreement {
  int rays = 0, hits = 0, same = 0, ties = 0;
  // Disagreements settled by testing every triangle (a tree of one leaf): the kd-tree's
  // errors, and the compact BVH's.
  int kd_wrong = 0, bvh_wrong = 0, kd_occlusion_wrong = 0, bvh_occlusion_wrong = 0;
  // The kd-tree's misses of a hit that Moller-Trumbore places well outside the triangle's
  // box (by 1e-5 of the largest coordinate, ~80 ulps; seen: a ray grazing a shared vertex,
  // where t is ill-conditioned, 1e-4 off). No structure with exact cells can promise those.
  int kd_ambiguous = 0;
  // The BVH's misses of a hit that Moller-Trumbore places outside the triangle's exact box
  // (its slab test's slack is relative to t, a few ulps): rays aimed exactly at a vertex,
  // which the triangles' decoded corners now match to float precision (the coarse grid
  // before the cell table moved them off the rays' targets).
  int bvh_ambiguous = 0;
};

bool same_distance(const Hit& a, const Hit& b) { return std::fabs(a.t - b.t) <= 1e-5f * b.t; }

// Both miss, or both hit at the same distance (on the same triangle or on a tie).
bool agree(bool a, const Hit& ha, bool b, const Hit& hb) {
  return a == b && (!a || same_distance(ha, hb));
}

bool inside_triangle_box(const CompactMesh& m, const Hit& h, const Ray& ray) {
  Bounds3 b;
  for (int k = 0; k < 3; ++k) b.extend(m.corner(h.prim, k));
  const Vec3 p = ray.org + ray.dir * h.t;
  for (int a = 0; a < 3; ++a)
    if (p[a] < b.lo[a] || p[a] > b.hi[a]) return false;
  return true;
}

bool near_triangle_box(const CompactMesh& m, const Hit& h, const Ray& ray) {
  float largest = 0;
  for (const QuantizedPosition& q : m.positions) {
    const Vec3 p = decode_position(m.grid, q);
    largest = std::max({largest, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  }
  const float pad = 1e-5f * largest;
  Bounds3 b;
  for (int k = 0; k < 3; ++k) b.extend(m.corner(h.prim, k));
  const Vec3 p = ray.org + ray.dir * h.t;
  for (int a = 0; a < 3; ++a)
    if (p[a] < b.lo[a] - pad || p[a] > b.hi[a] + pad) return false;
  return true;
}

Agreement compare(const CompactScene& c, const CompactKdTree& kd, const std::vector<Ray>& rays) {
  const CompactKdTree every_triangle = build_compact_kdtree(c.mesh, {.leaf_triangles = 1 << 30});
  Agreement g;
  for (const Ray& ray : rays) {
    ++g.rays;
    Hit hb, hk, hr;
    const bool b = compact_intersect(c, nullptr, ray, hb);
    const bool k = kdtree_intersect(kd, c.mesh, ray, hk);
    if (agree(k, hk, b, hb)) {
      g.hits += b;
      g.same += b && hk.prim == hb.prim;
      g.ties += b && hk.prim != hb.prim;  // coplanar triangles, or a ray through an edge
    } else {
      const bool r = kdtree_intersect(every_triangle, c.mesh, ray, hr);
      if (agree(k, hk, r, hr))
        ++(r && !inside_triangle_box(c.mesh, hr, ray) ? g.bvh_ambiguous : g.bvh_wrong);
      else if (r && !near_triangle_box(c.mesh, hr, ray))
        ++g.kd_ambiguous;
      else
        ++g.kd_wrong;
    }
    const bool ob = compact_occluded(c, nullptr, ray), ok = kdtree_occluded(kd, c.mesh, ray);
    if (ob != ok)
      (ok == kdtree_occluded(every_triangle, c.mesh, ray) ? g.bvh_occlusion_wrong
                                                          : g.kd_occlusion_wrong)++;
  }
  return g;
}

// Both forms: leaf-only (inner_refs_max 0) and Choi et al.'s (the defaults), whose inner
// nodes' triangles the traversal must test (the Cornell box's walls straddle the top
// splits, so rays hit triangles held only by inner nodes).
TEST(CompactKdTree, FindsTheClosestHitsAndOcclusionOfTheCompactBvh) {
  const Scene scenes[] = {make_cornell_box(), make_lit_sphere(0.8f, 48, 96, true),
                          cluttered_scene()};
  const KdBuildOptions options[] = {{.inner_refs_max = 0},
                                    {.max_depth = 3, .inner_refs_max = 0},
                                    {.leaf_triangles = 8, .inner_refs_max = 0},
                                    {},
                                    {.max_depth = 3},
                                    {.leaf_triangles = 8}};
  for (const Scene& scene : scenes) {
    const CompactScene c = build_compact_scene(scene);
    for (const KdBuildOptions& o : options) {
      const CompactKdTree kd = build_compact_kdtree(c.mesh, o);
      if (o.inner_refs_max > 0 && o.max_depth == 0) {
        EXPECT_GT(kd.inner_refs, 0u) << scene.name;  // or the Choi form is not tested
      }
      const Agreement g = compare(c, kd, random_rays(scene, 40000, 3));
      std::printf(
          "%s (max depth %d, leaf %d, inner %d): %zu nodes, %zu refs + %zu inner; %d rays, "
          "%d agreed hits (%d ties); kd-tree wrong %d (occlusion %d, ambiguous %d), bvh "
          "wrong %d (occlusion %d, ambiguous %d)\n",
          scene.name.c_str(), o.max_depth, o.leaf_triangles, o.inner_refs_max, kd.tree_nodes(),
          kd.refs.size(), kd.inner_refs, g.rays, g.hits, g.ties, g.kd_wrong, g.kd_occlusion_wrong,
          g.kd_ambiguous, g.bvh_wrong, g.bvh_occlusion_wrong, g.bvh_ambiguous);
      EXPECT_GT(g.hits, g.rays / 4) << scene.name;
      EXPECT_EQ(g.kd_wrong, 0) << scene.name;
      EXPECT_EQ(g.kd_occlusion_wrong, 0) << scene.name;
      EXPECT_LE(g.kd_ambiguous, g.rays / 10000) << scene.name;
      // A quarter of the rays aim exactly at a vertex, which the decoded corners match to
      // float precision since the cell table: such a hit may go to any triangle of the
      // vertex (2.8% of hits on the sphere; under 1% with the coarse whole-box grid).
      EXPECT_LE(g.ties, g.hits / 25) << scene.name;
      // The BVH too: its slab test's exit distance has slack (compact_accel.cpp box_hit);
      // without it, rays aimed at the Cornell box's corner vertices lost 19 closest hits
      // and 17 occlusions in 40,000.
      EXPECT_EQ(g.bvh_wrong, 0) << scene.name;
      EXPECT_LE(g.bvh_ambiguous, g.rays / 500) << scene.name;
      EXPECT_EQ(g.bvh_occlusion_wrong, 0) << scene.name;
    }
  }
}

// In both forms: every triangle is referenced, children are in range and stored in pairs
// after their parent, leaf ranges tile the reference array, the counts match, and the
// depth respects the limit.
TEST(CompactKdTree, IsWellFormed) {
  const Scene scene = cluttered_scene();
  const CompactMesh mesh = build_compact_mesh(scene);
  const size_t n = scene.triangle_count();
  for (const int inner : {0, 2}) {
    const CompactKdTree kd = build_compact_kdtree(mesh, {.inner_refs_max = inner});
    ASSERT_FALSE(kd.nodes.empty());
    EXPECT_EQ(kd.bytes(), kd.nodes.size() * 8 + kd.refs.size() * 4);
    EXPECT_EQ(kd.tree_nodes() % 2, 1u);  // a root and pairs of children
    EXPECT_LE(kd.depth, int(8 + 1.3 * std::log2(double(n))));
    EXPECT_GT(kd.depth, 5);
    const kdtree_walk::Walk w = kdtree_walk::walk(kd, n);
    ASSERT_TRUE(w.ok);
    EXPECT_EQ(w.nodes + w.slots, kd.nodes.size());  // every entry reached once
    EXPECT_EQ(w.nodes, kd.tree_nodes());
    EXPECT_EQ(w.slots, kd.slots);
    EXPECT_EQ(w.inner_refs, kd.inner_refs);
    EXPECT_EQ(w.leaf_refs, kd.refs.size());
    EXPECT_EQ(w.depth, kd.depth);
    for (size_t t = 0; t < n; ++t) EXPECT_GE(w.seen[t], 1) << "triangle " << t;
    EXPECT_GE(kd.all_refs(), n);
  }
}

Scene one_triangle(Vec3 a, Vec3 b, Vec3 c) {
  Scene s = make_cornell_box();
  s.positions = {a, b, c};
  s.normals.clear(), s.uvs.clear();
  s.indices = {0, 1, 2};
  s.material_ids = {0};
  return s;
}

TEST(CompactKdTree, DegenerateScenesDoNotBreakIt) {
  // All vertices equal: a one-leaf tree that nothing hits.
  const CompactMesh point =
      build_compact_mesh(one_triangle(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)));
  const CompactKdTree kp = build_compact_kdtree(point);
  for (const Vec3 d : {Vec3(0, 0, -1), normalize(Vec3(1, 1, 1)), Vec3(1, 0, 0)}) {
    Hit h;
    const Ray ray{Vec3(1, 1, 1) - d * 2.0f, d};
    EXPECT_FALSE(kdtree_intersect(kp, point, ray, h));
    EXPECT_FALSE(kdtree_occluded(kp, point, ray));
  }
  // No triangles at all.
  const CompactKdTree empty = build_compact_kdtree(CompactMesh{});
  EXPECT_TRUE(empty.nodes.empty());
  Hit h;
  EXPECT_FALSE(kdtree_intersect(empty, point, Ray{Vec3(0.0f), Vec3(0, 0, 1)}, h));
  // One flat triangle: hit where the BVH hits it, also by rays in its plane's directions.
  const CompactScene tri =
      build_compact_scene(one_triangle(Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)));
  const CompactKdTree kt = build_compact_kdtree(tri.mesh);
  EXPECT_EQ(kt.refs.size(), 1u);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 org(u(rng), u(rng), i % 2 ? 2.0f : 0.0f);
    const Vec3 dir = i % 2 ? normalize(Vec3(u(rng), u(rng), -3.0f)) : Vec3(1, 0, 0);
    const Ray ray{org, dir};
    Hit hb, hk;
    const bool b = compact_intersect(tri, nullptr, ray, hb);
    ASSERT_EQ(kdtree_intersect(kt, tri.mesh, ray, hk), b) << i;
    EXPECT_EQ(kdtree_occluded(kt, tri.mesh, ray), b) << i;
    if (b) {
      EXPECT_EQ(hk.t, hb.t);
    }
    hits += b;
  }
  EXPECT_GT(hits, 100);
}

}  // namespace compact_kdtree_test
}  // namespace multiray
