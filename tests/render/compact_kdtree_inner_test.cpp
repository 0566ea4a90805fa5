// The compact kd-tree's form after Choi, Chang & Ihm (render/compact_kdtree.h): our reading
// of its two measures (compact_kdtree_inner.h), fewer references than the leaf-only tree
// on a scene of big straddling triangles, the per-node and per-path budgets, and the
// leaf-only tree when the form is off. Its hits: compact_kdtree_test.cpp.
#include <gtest/gtest.h>

#include <stdexcept>

#include "kdtree_walk.h"
#include "render/compact_kdtree.h"
#include "render/compact_kdtree_inner.h"
#include "scene/builders.h"

namespace multiray {
namespace compact_kdtree_inner_test {

// The Cornell box's walls (big triangles that the top splits cut), a dense sphere and a
// big quad across the room.
Scene straddler_scene() {
  Scene s = make_cornell_box();
  const uint32_t m = s.material_ids.front();
  add_sphere(s, Vec3(0.3f, 0.5f, 0.2f), 0.3f, 24, 48, false, m);
  add_quad(s, Vec3(-1, 0.2f, -1), Vec3(1, 1.8f, -1), Vec3(1, 1.8f, 1), Vec3(-1, 0.2f, 1), m);
  return s;
}

Bounds3 box(Vec3 lo, Vec3 hi) { return Bounds3{lo, hi}; }

TEST(CompactKdTreeChoi, MeasuresFollowOurReading) {
  const Bounds3 cell = box(Vec3(0, 0, 0), Vec3(1, 2, 1));
  // A floor across the whole cell: all of the x-z face, none of the other two.
  EXPECT_FLOAT_EQ(kd_inner::occupancy(box(Vec3(0, 1, 0), Vec3(1, 1, 1)), cell), 1.0f);
  // Half the cell in x and in z, flat in y: a quarter of the x-z face.
  EXPECT_FLOAT_EQ(kd_inner::occupancy(box(Vec3(0, 1, 0), Vec3(0.5f, 1, 0.5f)), cell), 0.25f);
  // Across x and y (the x-y face is 1 x 2): 0.5 x 0.5 of it.
  EXPECT_FLOAT_EQ(kd_inner::occupancy(box(Vec3(0, 0, 0.5f), Vec3(0.5f, 1, 0.5f)), cell), 0.25f);

  // Candidate planes: x at 0.1 .. 0.9 (and the cell's own bounds and a repeat, skipped),
  // one z plane at 0.5.
  kd_inner::CandidatePlanes planes;
  for (int a = 0; a < 3; ++a) planes.clear(a);
  for (const float x : {0.0f, 0.1f, 0.2f, 0.3f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f})
    planes.add(0, x, cell);
  planes.add(2, 0.5f, cell);
  ASSERT_EQ(planes.size(), 10u);
  // Strictly inside [0.25, 0.75] in x: 0.3 .. 0.7, five; the z plane at its bound is not.
  EXPECT_FLOAT_EQ(planes.frequency(box(Vec3(0.25f, 0, 0), Vec3(0.75f, 2, 0.5f))), 0.5f);
  EXPECT_FLOAT_EQ(planes.frequency(box(Vec3(0, 0, 0), Vec3(1, 2, 1))), 1.0f);

  // The picker: both thresholds, best frequency first, at most `room`.
  kd_inner::InnerPicker pick(cell, planes, 0.5f, 0.4f, 1);
  pick.offer(7, box(Vec3(0.25f, 1, 0), Vec3(0.75f, 1, 1)));   // occupancy 0.5, frequency 0.6
  pick.offer(8, box(Vec3(0.0f, 1, 0), Vec3(0.5f, 1, 0.5f)));  // occupancy 0.25: no
  pick.offer(9, box(Vec3(0.0f, 1, 0), Vec3(1.0f, 1, 1)));     // occupancy 1, frequency 1
  ASSERT_EQ(pick.count(), 1);
  EXPECT_EQ(pick.picked(0), 9u);
  EXPECT_FALSE(pick.contains(7));
}

TEST(CompactKdTreeChoi, HasFewerReferencesWithinItsBudgets) {
  const Scene scene = straddler_scene();
  const CompactMesh mesh = build_compact_mesh(scene);
  const size_t n = scene.triangle_count();
  const CompactKdTree leaf = build_compact_kdtree(mesh, {.inner_refs_max = 0});
  const CompactKdTree seo = build_compact_kdtree(mesh);  // Seo et al.'s (2, 8, 0.5, 0.4)
  std::printf(
      "leaf-only: %zu nodes, %zu refs, %zu bytes; seo: %zu nodes, %zu + %zu refs, %zu "
      "bytes\n",
      leaf.tree_nodes(), leaf.refs.size(), leaf.bytes(), seo.tree_nodes(), seo.refs.size(),
      seo.inner_refs, seo.bytes());
  EXPECT_LT(seo.all_refs(), leaf.refs.size());
  EXPECT_GT(seo.inner_refs, 0u);
  struct Budget {
    int node, path;
  };
  for (const Budget b : {Budget{2, 8}, Budget{1, 3}, Budget{2, 3}, Budget{2, 1}}) {
    const CompactKdTree kd =
        build_compact_kdtree(mesh, {.inner_refs_max = b.node, .path_refs_max = b.path});
    const kdtree_walk::Walk w = kdtree_walk::walk(kd, n);
    ASSERT_TRUE(w.ok);
    EXPECT_EQ(w.inner_refs, kd.inner_refs);
    EXPECT_LE(w.most_in_a_node, b.node) << b.node << "/" << b.path;
    EXPECT_LE(w.most_on_a_path, b.path) << b.node << "/" << b.path;
    for (size_t t = 0; t < n; ++t) ASSERT_GE(w.seen[t], 1) << "triangle " << t;
    if (b.path <= 3) {  // the budget binds: some path uses all of it
      EXPECT_EQ(w.most_on_a_path, b.path) << b.node << "/" << b.path;
    }
  }
}

bool same_tree(const CompactKdTree& a, const CompactKdTree& b) {
  if (a.nodes.size() != b.nodes.size() || a.refs != b.refs || a.depth != b.depth) return false;
  for (size_t i = 0; i < a.nodes.size(); ++i)
    if (a.nodes[i].payload != b.nodes[i].payload || a.nodes[i].link != b.nodes[i].link)
      return false;
  return true;
}

// inner_refs_max = 0 is Wald & Havran's tree: the same as when no triangle passes the
// thresholds or the path has no room, with no slot and no node flagged.
TEST(CompactKdTreeChoi, NoInnerReferencesIsTheLeafOnlyTree) {
  const CompactMesh mesh = build_compact_mesh(straddler_scene());
  const CompactKdTree leaf = build_compact_kdtree(mesh, {.inner_refs_max = 0});
  EXPECT_EQ(leaf.slots, 0u);
  EXPECT_EQ(leaf.inner_refs, 0u);
  const kdtree_walk::Walk w = kdtree_walk::walk(leaf, mesh.indices.size() / 3);
  EXPECT_EQ(w.slots, 0u);
  EXPECT_EQ(w.nodes, leaf.nodes.size());
  EXPECT_TRUE(same_tree(leaf, build_compact_kdtree(mesh, {.path_refs_max = 0})));
  EXPECT_TRUE(same_tree(leaf, build_compact_kdtree(mesh, {.tau_occu = 2.0f})));
  EXPECT_TRUE(same_tree(leaf, build_compact_kdtree(mesh, {.tau_freq = 2.0f})));
  EXPECT_FALSE(same_tree(leaf, build_compact_kdtree(mesh)));
  EXPECT_THROW(build_compact_kdtree(mesh, {.inner_refs_max = 3}), std::invalid_argument);
  EXPECT_THROW(build_compact_kdtree(mesh, {.inner_refs_max = -1}), std::invalid_argument);
}

}  // namespace compact_kdtree_inner_test
}  // namespace multiray
