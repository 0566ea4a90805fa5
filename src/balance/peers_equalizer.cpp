#include "balance/peers_equalizer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>

#include "partition/weight_map.h"

namespace multiray::balance {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Axes of `node` and below from an even split of a w×h part, as Equalizer's _update
// halves each node's viewport: columns (cut along x) when the part is wider than high.
void set_axes(const std::vector<EqualizerBalancer::Node>& tree, std::vector<char>& columns,
              int node, double w, double h) {
  const EqualizerBalancer::Node& n = tree[size_t(node)];
  if (n.left < 0) return;
  const bool c = w > h;
  columns[size_t(node)] = c;
  set_axes(tree, columns, n.left, c ? w / 2 : w, c ? h : h / 2);
  set_axes(tree, columns, n.right, c ? w / 2 : w, c ? h : h / 2);
}

// Length of [a0, a1] ∩ [b0, b1], 0 if they do not overlap.
double overlap(double a0, double a1, double b0, double b1) {
  return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}
}  // namespace

EqualizerBalancer::EqualizerBalancer(int device_count, double damping)
    : BalancerBase(device_count), damping_(damping) {
  build(0, device_count);
}

std::string EqualizerBalancer::spec() const {
  std::ostringstream s;
  s << "equalizer:damping=" << damping_;
  return s.str();
}

int EqualizerBalancer::build(int first, int count) {
  const int index = int(tree_.size());
  tree_.push_back(Node{first, count, -1, -1});
  if (count > 1) {
    const int middle = count / 2;  // Equalizer: left = the first size >> 1 children
    const int left = build(first, middle);
    const int right = build(first + middle, count - middle);
    tree_[size_t(index)].left = left;
    tree_[size_t(index)].right = right;
  }
  return index;
}

int EqualizerBalancer::alive_in(const Node& n) const {
  int k = 0;
  for (int i = n.first; i < n.first + n.count; ++i) k += alive(i) ? 1 : 0;
  return k;
}

double EqualizerBalancer::cut(int view, int node) const {
  if (view < 0 || size_t(view) >= cuts_.size() || node < 0 || size_t(node) >= tree_.size())
    return kNaN;
  return cuts_[size_t(view)][size_t(node)];
}

bool EqualizerBalancer::cuts_columns(int node) const {
  return node >= 0 && size_t(node) < columns_.size() && columns_[size_t(node)];
}

void EqualizerBalancer::reset(const FrameShape& shape) {
  shape_ = FrameShape{shape.width, shape.height, shape.views, {}};
  columns_.assign(tree_.size(), 0);
  set_axes(tree_, columns_, 0, double(shape.width), double(shape.height));
  cuts_.assign(size_t(std::max(shape.views, 0)), std::vector<double>(tree_.size(), kNaN));
  for (std::vector<double>& cuts : cuts_) reset_cuts(0, Region{0, 0, 1, 1}, cuts);
  planned_.assign(size_t(device_count()), std::vector<Rect>(cuts_.size()));
}

void EqualizerBalancer::reset_cuts(int node, Region r, std::vector<double>& cuts) const {
  const Node& n = tree_[size_t(node)];
  if (n.left < 0) return;
  const bool c = columns_[size_t(node)];
  const double lo = c ? r.x0 : r.y0, hi = c ? r.x1 : r.y1;
  const int al = alive_in(tree_[size_t(n.left)]), ar = alive_in(tree_[size_t(n.right)]);
  const double pos = al + ar == 0 ? lo : lo + (hi - lo) * al / (al + ar);
  cuts[size_t(node)] = pos;
  Region left = r, right = r;
  (c ? left.x1 : left.y1) = pos;
  (c ? right.x0 : right.y0) = pos;
  reset_cuts(n.left, left, cuts);
  reset_cuts(n.right, right, cuts);
}

void EqualizerBalancer::on_drop(int /*index*/) {
  if (!cuts_.empty()) reset(shape_);
}

Plan EqualizerBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  if (cuts_.empty() || !shape_.same_size(shape)) reset(shape);
  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  if (shape.pixels() == 0) {
    plan.ratios = even();
    return plan;
  }
  for (int view = 0; view < shape.views; ++view)
    place(0, Rect{0, 0, shape.width, shape.height}, view, cuts_[size_t(view)], plan);
  for (std::vector<Rect>& rects : planned_) std::fill(rects.begin(), rects.end(), Rect{});
  for (size_t i = 0; i < plan.assigned.size(); ++i)
    for (const WorkItem& item : plan.assigned[i]) planned_[i][size_t(item.view)] = item.rect;
  const WeightMap weights(shape.width, shape.height, shape.views, shape.pixel_weight);
  std::vector<double> share(size_t(device_count()), 0.0);
  for (size_t i = 0; i < share.size(); ++i) share[i] = weights.sum(plan.assigned[i]);
  plan.ratios = sanitize(share, even());
  return plan;
}

void EqualizerBalancer::place(int node, Rect r, int view, const std::vector<double>& cuts,
                              Plan& plan) const {
  const Node& n = tree_[size_t(node)];
  if (n.left < 0) {
    if (alive(n.first) && !r.empty()) plan.assigned[size_t(n.first)].push_back(WorkItem{r, view});
    return;
  }
  const bool c = columns_[size_t(node)];
  const int lo = c ? r.x0 : r.y0, hi = c ? r.x1 : r.y1;
  const int al = alive_in(tree_[size_t(n.left)]), ar = alive_in(tree_[size_t(n.right)]);
  int pos;
  if (al == 0) {
    pos = lo;
  } else if (ar == 0) {
    pos = hi;
  } else {
    const double cut = cuts[size_t(node)] * (c ? shape_.width : shape_.height);
    pos = std::isfinite(cut) ? int(std::lround(cut)) : (lo + hi) / 2;
    pos = std::clamp(pos, lo, hi);
  }
  Rect left = r, right = r;
  (c ? left.x1 : left.y1) = pos;
  (c ? right.x0 : right.y0) = pos;
  place(n.left, left, view, cuts, plan);
  place(n.right, right, view, cuts, plan);
}

void EqualizerBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  if (alive_count() == 0 || cuts_.empty() || shape_.pixels() == 0) return;
  if (!stats.shape.same_size(shape_)) return;
  const int views = shape_.views;
  const double w = shape_.width, h = shape_.height;

  // The planned rectangles hold what each device rendered (no queue, no stealing); its
  // time is split over its views by the item reports, or by area without usable ones.
  std::vector<Rect> rects;  // planned rects of the device, by view
  std::vector<std::vector<Load>> loads(static_cast<size_t>(views));
  for (int i = 0; i < device_count(); ++i) {
    if (!alive(i)) continue;
    rects.clear();
    for (int v = 0; v < views; ++v) {
      Rect r;
      if (size_t(i) < planned_.size() && size_t(v) < planned_[size_t(i)].size())
        r = planned_[size_t(i)][size_t(v)];
      rects.push_back(r);
    }
    double area = 0;
    for (const Rect& r : rects) area += double(r.area());
    if (area == 0) continue;  // rendered nothing, measured nothing
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms)) return;  // incomplete frame: keep the cuts

    std::vector<double> per_view(size_t(views), 0.0);
    bool items_usable = !d->items.empty();
    for (const ItemReport& item : d->items) {
      const int v = item.item.view;
      if (v < 0 || v >= views || rects[size_t(v)].empty() || !std::isfinite(item.time_ms) ||
          item.time_ms < 0) {
        items_usable = false;
        break;
      }
      per_view[size_t(v)] += item.time_ms;
    }
    double sum = 0;
    for (double t : per_view) sum += t;
    for (int v = 0; v < views; ++v) {
      double& t = per_view[size_t(v)];
      t = items_usable && valid_time(sum) ? t / sum * d->time_ms
                                          : d->time_ms * double(rects[size_t(v)].area()) / area;
    }
    for (int v = 0; v < views; ++v) {
      const Rect& r = rects[size_t(v)];
      if (r.empty()) continue;
      loads[size_t(v)].push_back(
          Load{r.x0 / w, r.y0 / h, r.x1 / w, r.y1 / h, per_view[size_t(v)]});
    }
  }

  std::vector<std::vector<double>> next = cuts_;
  for (int v = 0; v < views; ++v) {
    recut(0, Region{0, 0, 1, 1}, loads[size_t(v)], next[size_t(v)]);
    for (size_t k = 0; k < tree_.size(); ++k)
      if (tree_[k].left >= 0 && !std::isfinite(next[size_t(v)][k])) return;
  }
  cuts_ = std::move(next);
}

double EqualizerBalancer::time_below(const std::vector<Load>& loads, const Region& r, bool columns,
                                     double pos) {
  double t = 0;
  for (const Load& l : loads) {
    const double a0 = columns ? l.x0 : l.y0, a1 = columns ? l.x1 : l.y1;
    const double b0 = columns ? l.y0 : l.x0, b1 = columns ? l.y1 : l.x1;
    if (!(a1 > a0) || !(b1 > b0)) continue;  // Equalizer's _removeEmpty
    const double lo = columns ? r.x0 : r.y0;
    const double p0 = columns ? r.y0 : r.x0, p1 = columns ? r.y1 : r.x1;
    t += l.ms * (overlap(lo, pos, a0, a1) / (a1 - a0)) * (overlap(p0, p1, b0, b1) / (b1 - b0));
  }
  return t;
}

void EqualizerBalancer::recut(int node, Region r, const std::vector<Load>& all,
                              std::vector<double>& cuts) {
  const Node& n = tree_[size_t(node)];
  if (n.left < 0) return;
  // Only the loads overlapping this part matter here and below.
  std::vector<Load> loads;
  for (const Load& l : all)
    if (overlap(r.x0, r.x1, l.x0, l.x1) > 0 && overlap(r.y0, r.y1, l.y0, l.y1) > 0)
      loads.push_back(l);

  const bool c = columns_[size_t(node)];
  const double lo = c ? r.x0 : r.y0, hi = c ? r.x1 : r.y1;
  const int al = alive_in(tree_[size_t(n.left)]), ar = alive_in(tree_[size_t(n.right)]);
  double pos;
  if (al == 0 || ar == 0) {
    pos = al == 0 ? lo : hi;
  } else {
    const double share = double(al) / (al + ar);
    double want = lo + (hi - lo) * share;  // no measured time here: split the area
    const double total = time_below(loads, r, c, hi);
    if (valid_time(total) && hi > lo) {
      // Walk the breakpoints of the piecewise-linear time along the axis to the target.
      const double target = total * share;
      std::vector<double> at = {lo, hi};
      for (const Load& l : loads)
        for (double e : {c ? l.x0 : l.y0, c ? l.x1 : l.y1})
          if (e > lo && e < hi) at.push_back(e);
      std::sort(at.begin(), at.end());
      double prev_pos = lo, prev_t = 0;
      for (size_t k = 1; k < at.size(); ++k) {
        const double t = time_below(loads, r, c, at[k]);
        if (t >= target && t > prev_t) {
          want = prev_pos + (at[k] - prev_pos) * (target - prev_t) / (t - prev_t);
          break;
        }
        prev_pos = at[k];
        prev_t = t;
      }
    }
    const double previous = std::isfinite(cuts[size_t(node)]) ? cuts[size_t(node)] : want;
    pos = std::clamp((1 - damping_) * want + damping_ * previous, lo, hi);
  }
  cuts[size_t(node)] = pos;
  Region left = r, right = r;
  (c ? left.x1 : left.y1) = pos;
  (c ? right.x0 : right.y0) = pos;
  recut(n.left, left, loads, cuts);
  recut(n.right, right, loads, cuts);
}

}  // namespace multiray::balance
