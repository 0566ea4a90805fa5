// `equalizer`: the load equalizer of Equalizer (Eilemann, Makhinya & Pajarola,
// "Equalizer: A Scalable Parallel Rendering Framework", IEEE TVCG 15(3), 2009;
// eq/server/equalizers/loadEqualizer.cpp, 2D mode), rewritten from its published sources
// so that multiray can be measured against it. The facts are Equalizer's; the code is ours.
//
// Tree. The devices are the leaves of a binary tree: a node holds devices [a, b), its
// left child the first half (rounded down), its right child the rest. Every node splits
// its part of the view in two along one axis, so each device gets one rectangle per view
// (a k-d tree). The axis is the longer side of the node's part in an even split of the
// view (Equalizer 1.x, `pvp.w > pvp.h`: columns, else rows); for ordinary aspect ratios
// the axes alternate level by level.
//
// Split. From the last usable frame, each device's time on each view and the rectangle it
// rendered give a time per area, taken as uniform inside the rectangle. A node splits
// the measured time of its part in proportion to its alive devices on either side: it
// walks along its axis accumulating the time of every measured rectangle overlapping
// the slab, and cuts where the left side's share is reached (interpolating inside a
// rectangle). The new cut is then damped toward the node's previous cut,
//   cut ← (1 − damping) · cut + damping · previous cut,
// Equalizer's `damping` (default 0.5). Equalizer hands each child its target time; we
// hand it the measured time of the part it really got after damping, so a damped cut
// cannot starve a subtree. Each view has its own tree of cuts, measured on that view.
//
// Equalizer starts from an even split by resources (its fake first frame of uniform
// load); so do we, and again when the frame size or view count changes or a device is
// dropped (a dropped device's side of every cut gets nothing). Cuts are kept in
// normalised view coordinates and rounded to whole pixels per plan, so the rectangles
// tile every view exactly. Area, not pixel_weight, is split (the measured times already
// contain the cost); Plan::ratios are the devices' shares of the frame's samples.
// A frame is used only if it has the planned size and every alive device that was given
// pixels reported a usable time; anything else leaves the cuts as they are.
//
// | parameter | default | meaning                                                  |
// |-----------|---------|----------------------------------------------------------|
// | damping   | 0.5     | weight of the previous cut, [0, 1]: 0 follows the last   |
// |           |         | frame alone, 1 freezes the cuts                          |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class EqualizerBalancer final : public BalancerBase {
 public:
  explicit EqualizerBalancer(int device_count, double damping = 0.5);

  std::string name() const override { return "equalizer"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

  // A node of the k-d tree over the devices [first, first + count).
  struct Node {
    int first = 0, count = 0;
    int left = -1, right = -1;  // child nodes; -1 for a leaf (count == 1)
  };
  const std::vector<Node>& tree() const { return tree_; }
  // Cut of `node` in `view`, in normalised view coordinates along its axis (x for
  // columns, y for rows); NaN before the first plan.
  double cut(int view, int node) const;
  // True if `node` cuts columns (along x) for the last planned shape.
  bool cuts_columns(int node) const;

 private:
  // A measured rectangle in normalised coordinates and its time (ms).
  struct Load {
    double x0, y0, x1, y1, ms;
  };
  struct Region {
    double x0, y0, x1, y1;
  };

  int build(int first, int count);
  int alive_in(const Node& n) const;
  // Axes from an even split of a width×height view; cuts reset to an even split by
  // alive devices.
  void reset(const FrameShape& shape);
  void reset_cuts(int node, Region r, std::vector<double>& cuts) const;
  // Time of `loads` inside the part of `r` below `pos` along `columns`' axis.
  static double time_below(const std::vector<Load>& loads, const Region& r, bool columns,
                           double pos);
  void recut(int node, Region r, const std::vector<Load>& loads, std::vector<double>& cuts);
  void place(int node, Rect r, int view, const std::vector<double>& cuts, Plan& plan) const;
  void on_drop(int index) override;

  double damping_;
  std::vector<Node> tree_;
  std::vector<char> columns_;               // per node: cuts along x
  std::vector<std::vector<double>> cuts_;   // [view][node]
  FrameShape shape_;                        // size the cuts are for (no weights kept)
  std::vector<std::vector<Rect>> planned_;  // [device][view] rects of the last plan
};

}  // namespace multiray::balance
