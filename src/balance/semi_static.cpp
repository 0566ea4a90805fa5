#include "balance/semi_static.h"

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <stdexcept>

#include "partition/cdf_split.h"
#include "partition/scanline.h"

namespace multiray::balance {

SemiStaticBalancer::SemiStaticBalancer(int device_count, SemiStaticOptions options)
    : BalancerBase(device_count), options_(options), shares_(even()) {}

std::string SemiStaticBalancer::spec() const {
  std::ostringstream s;  // shortest form, e.g. 0.4 (std::to_string gives 0.400000)
  s << "semi-static:alpha=" << options_.alpha;
  if (options_.split == LineAxis::rows) s << ":split=rows";
  if (options_.cdf_from_frame) s << ":cdf=frame";
  if (options_.whole_lines) s << ":cut=line";
  return s.str();
}

void SemiStaticBalancer::on_drop(int /*index*/) { shares_ = sanitize(shares_, even()); }

std::vector<double> SemiStaticBalancer::line_weights(const FrameShape& shape) const {
  const bool rows = options_.split == LineAxis::rows;
  if (shape.weighted() && options_.cdf_from_frame) {
    const WeightMap map(shape.width, shape.height, shape.views, shape.pixel_weight);
    return rows ? flat_row_weights(map) : flat_column_weights(map);
  }
  // Pixels per line times the samples per pixel reported there last frame. The density
  // stays meaningful when only the other dimension changed: e.g. rows of a band whose
  // width the level above changes (Harada's second level).
  const int lines = rows ? shape.height : shape.width;
  std::vector<double> w(size_t(shape.views) * size_t(lines), rows ? shape.width : shape.height);
  const bool same_lines = density_shape_.views == shape.views &&
                          (rows ? density_shape_.height : density_shape_.width) == lines;
  if (same_lines && density_.size() == w.size())
    for (size_t c = 0; c < w.size(); ++c) w[c] *= density_[c];
  return w;
}

Plan SemiStaticBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0 || shape.pixels() == 0) return empty_plan();
  Plan plan;
  plan.ratios = shares_;
  plan.assigned.resize(size_t(device_count()));
  const std::vector<double> weights = line_weights(shape);
  // Cut at pixel precision along the lines (a line's weight spread evenly over it).
  const bool rows = options_.split == LineAxis::rows;
  const int64_t line = rows ? shape.width : shape.height;
  std::vector<int64_t> cuts = cdf_cuts(weights, line, shares_);
  if (options_.whole_lines)  // nearest line: rounding keeps the cuts in order
    for (int64_t& c : cuts) c = (c + line / 2) / line * line;
  for (int i = 0; i < device_count(); ++i) {
    const int64_t begin = cuts[size_t(i)], end = cuts[size_t(i) + 1];
    std::vector<WorkItem>& out = plan.assigned[size_t(i)];
    if (rows)
      append_flat_range(shape.width, shape.height, begin, end, out);
    else
      append_flat_column_range(shape.width, shape.height, begin, end, out);
  }
  return plan;
}

void SemiStaticBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  if (alive_count() == 0) return;

  // Harada's step over the devices with a usable measurement; the others keep their share.
  const size_t n = size_t(device_count());
  std::vector<double> samples(n, 0.0), speed(n, 0.0);
  double mass = 0, total_samples = 0, total_speed = 0;
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms) || !(work_done(*d) > 0)) continue;
    samples[size_t(i)] = work_done(*d);
    speed[size_t(i)] = samples[size_t(i)] / d->time_ms;
    mass += shares_[size_t(i)];
    total_samples += samples[size_t(i)];
    total_speed += speed[size_t(i)];
  }
  if (total_samples > 0 && total_speed > 0 && mass > 0) {
    std::vector<double> next = shares_;
    for (size_t i = 0; i < n; ++i) {
      if (!(samples[i] > 0)) continue;
      const double now = mass * samples[i] / total_samples;  // n_i, as a share
      const double ideal = mass * speed[i] / total_speed;    // T·p_i = N·p_i/Σp, as a share
      next[i] = (1 - options_.alpha) * now + options_.alpha * ideal;
    }
    shares_ = sanitize(next, shares_);
  }
  learn_density(stats);
}

// Per-line samples per pixel from the item reports, for the next split.
void SemiStaticBalancer::learn_density(const FrameStats& stats) {
  if (stats.shape.pixels() == 0) return;
  WeightMap area(stats.shape.width, stats.shape.height, stats.shape.views, {});
  WeightMap weight;
  try {
    weight = WeightMap(stats.shape.width, stats.shape.height, stats.shape.views,
                       stats.shape.pixel_weight);
  } catch (const std::invalid_argument&) {
    weight = area;  // a malformed report: count pixels
  }
  LineDensity lines(area, options_.split);
  for (const DeviceFrameStats& d : stats.devices)
    for (const ItemReport& r : d.items)
      lines.add(r.item, r.samples > 0 ? r.samples : weight.sum(r.item));
  if (lines.empty()) return;
  density_ = lines.density(lines.mean(1.0));
  density_shape_ = stats.shape;
  density_shape_.pixel_weight.clear();
}

}  // namespace multiray::balance
