// Which straddling triangles an inner node of the compact kd-tree keeps (after Choi, Chang
// & Ihm, PG 2013, who keep one; two is Seo, Kim & Ihm's form, Sensors 2022; see
// compact_kdtree.h). Internal
// to compact_kdtree.cpp; declared here so that the measures can be tested on their own.
//
// THE TWO MEASURES ARE OUR READING. The paper's text was not at hand; Seo et al. give only
// the thresholds (tau_occu, tau_freq) = (0.5, 0.4). Both are computed for a triangle that
// straddles the node's split plane (a leaf-only tree would reference it in both children),
// from its bounds clipped to the node's cell, and both lie in [0, 1]:
//
// - occupancy: how much of the cell the triangle spans. For each of the three orientations
//   of the cell's faces, the fraction of that face that the clipped box covers (the product
//   of its two extents relative to the cell's); the largest of the three. A triangle that
//   spans the cell is met by most rays that enter the cell anyway, so testing it once at
//   the node wastes little. The face parallel to the split plane alone would not do: the
//   commonest big straddler, a floor or wall perpendicular to the plane, covers none of it.
//
// - frequency: how often the subtree would cut the triangle again. The builder splits below
//   at the node's candidate planes (the bounds of its references' clipped boxes, inside the
//   cell, all three axes); frequency is the fraction of those planes (distinct positions per
//   axis) that pass strictly through the triangle's clipped box, each of which would
//   duplicate it. Unlike occupancy it weighs where the geometry is: a triangle across empty
//   space is rarely cut, one across a dense region nearly always.
//
// A straddler is kept when occupancy >= tau_occu and frequency >= tau_freq, the highest
// frequency first (then occupancy, then the order offered), as many as the node's and the
// path's budgets allow. The alternative reading of frequency as the share of the node's
// references that straddle the plane was not taken: it describes the node, not the
// triangle, and is smallest high in the tree, where a big triangle is duplicated most (two
// floor triangles among 66,000 references at Sponza's root).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace multiray::kd_inner {

float occupancy(const Bounds3& clipped, const Bounds3& cell);

// A node's candidate planes: per axis, the distinct positions strictly inside the cell,
// ascending. Filled by the builder from its sorted sweep events.
class CandidatePlanes {
 public:
  void clear(int axis) { pos_[axis].clear(); }
  // Positions must come in ascending order; repeats and those outside the cell are skipped.
  void add(int axis, float pos, const Bounds3& cell);
  size_t size() const { return pos_[0].size() + pos_[1].size() + pos_[2].size(); }
  // The fraction of the planes strictly inside `clipped` (0 when there are none).
  float frequency(const Bounds3& clipped) const;

 private:
  std::vector<float> pos_[3];
};

// Keeps the best `room` (at most 2) of the straddlers offered that pass both thresholds.
class InnerPicker {
 public:
  InnerPicker(const Bounds3& cell, const CandidatePlanes& planes, float tau_occu, float tau_freq,
              int room);
  void offer(uint32_t index, const Bounds3& clipped);
  int count() const { return n_; }
  uint32_t picked(int i) const { return best_[i].index; }
  bool contains(uint32_t index) const;

 private:
  struct Candidate {
    uint32_t index;
    float freq, occu;
  };
  Bounds3 cell_;
  const CandidatePlanes& planes_;
  float tau_occu_, tau_freq_;
  int room_, n_ = 0;
  Candidate best_[2];
};

}  // namespace multiray::kd_inner
