// Test helper: walks a compact kd-tree (render/compact_kdtree.h) from its root, checking
// the layout's indices as it goes, and counts what it meets. (The node array cannot be
// read in order: a reference slot's words are triangle indices, not a node.)
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "render/compact_kdtree.h"

namespace multiray::kdtree_walk {

struct Walk {
  size_t nodes = 0, leaves = 0, slots = 0, inner_refs = 0, leaf_refs = 0;
  int depth = 0;
  int most_in_a_node = 0;  // inner references of one node
  int most_on_a_path = 0;  // inner references on one root-to-leaf path
  std::vector<int> seen;   // references per triangle, inner and leaf
  bool ok = true;          // every index in range (a failure is also reported)
};

inline void visit(const CompactKdTree& kd, uint32_t i, int depth, int path, Walk& w) {
  if (!w.ok) return;
  if (i >= kd.nodes.size()) {
    ADD_FAILURE() << "node " << i << " out of range", w.ok = false;
    return;
  }
  const KdNode n = kd.nodes[i];
  ++w.nodes;
  w.depth = std::max(w.depth, depth);
  const auto see = [&](uint32_t tri) {
    if (tri >= w.seen.size()) {
      ADD_FAILURE() << "triangle " << tri << " out of range", w.ok = false;
      return;
    }
    ++w.seen[tri];
  };
  if (n.leaf()) {
    ++w.leaves;
    w.most_on_a_path = std::max(w.most_on_a_path, path);
    if (size_t(n.index()) + n.count() > kd.refs.size()) {
      ADD_FAILURE() << "leaf " << i << " past the references", w.ok = false;
      return;
    }
    // Leaves were made depth first, lower child first: their ranges tile the array in
    // the walk's order.
    EXPECT_EQ(n.index(), w.leaf_refs) << "leaf " << i;
    for (uint32_t k = 0; k < n.count(); ++k) see(kd.refs[n.index() + k]);
    w.leaf_refs += n.count();
    return;
  }
  int here = 0;
  if (n.has_refs()) {
    if (n.children() == 0) {
      ADD_FAILURE() << "node " << i << ": slot before node 0", w.ok = false;
      return;
    }
    const KdNode slot = kd.nodes[n.children() - 1];
    ++w.slots;
    see(slot.first_ref()), ++here;
    if (slot.second_ref() != KdNode::kNoRef) see(slot.second_ref()), ++here;
  }
  w.inner_refs += size_t(here);
  w.most_in_a_node = std::max(w.most_in_a_node, here);
  EXPECT_GT(n.children(), i) << "children after their parent";
  visit(kd, n.children(), depth + 1, path + here, w);
  visit(kd, n.children() + 1, depth + 1, path + here, w);
}

inline Walk walk(const CompactKdTree& kd, size_t triangles) {
  Walk w;
  w.seen.assign(triangles, 0);
  if (!kd.nodes.empty()) visit(kd, 0, 0, 0, w);
  return w;
}

}  // namespace multiray::kdtree_walk
