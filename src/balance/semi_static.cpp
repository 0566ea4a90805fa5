#include "balance/semi_static.h"

#include <cstddef>
#include <sstream>
#include <stdexcept>

#include "balance/row_density.h"
#include "partition/cdf_split.h"
#include "partition/scanline.h"

namespace multiray::balance {

SemiStaticBalancer::SemiStaticBalancer(int device_count, double alpha)
    : BalancerBase(device_count), alpha_(alpha), shares_(even()) {}

std::string SemiStaticBalancer::spec() const {
  std::ostringstream s;  // shortest form, e.g. 0.4 (std::to_string gives 0.400000)
  s << "semi-static:alpha=" << alpha_;
  return s.str();
}

void SemiStaticBalancer::on_drop(int /*index*/) { shares_ = sanitize(shares_, even()); }

Plan SemiStaticBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0 || shape.pixels() == 0) return empty_plan();
  // Samples per flat row: this frame's own counts if known, else last frame's density.
  std::vector<double> row_weight;
  if (shape.weighted()) {
    row_weight =
        flat_row_weights(WeightMap(shape.width, shape.height, shape.views, shape.pixel_weight));
  } else {
    row_weight.assign(size_t(shape.views) * size_t(shape.height), double(shape.width));
    // Samples per pixel of each row stay meaningful when only the width changed: the
    // columns of a band whose height the level above changes (Harada's second level).
    if (density_shape_.views == shape.views && density_shape_.height == shape.height)
      for (size_t c = 0; c < row_weight.size(); ++c) row_weight[c] *= density_[c];
  }
  Plan plan;
  plan.ratios = shares_;
  plan.assigned.resize(size_t(device_count()));
  const std::vector<int64_t> cuts = cdf_cuts(row_weight, shape.width, shares_);
  for (int i = 0; i < device_count(); ++i)
    append_flat_range(shape.width, shape.height, cuts[size_t(i)], cuts[size_t(i) + 1],
                      plan.assigned[size_t(i)]);
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
      next[i] = (1 - alpha_) * now + alpha_ * ideal;
    }
    shares_ = sanitize(next, shares_);
  }

  // Per-row samples per pixel from the item reports, for the next split.
  if (stats.shape.pixels() == 0) return;
  WeightMap area(stats.shape.width, stats.shape.height, stats.shape.views, {});
  WeightMap weight;
  try {
    weight = WeightMap(stats.shape.width, stats.shape.height, stats.shape.views,
                       stats.shape.pixel_weight);
  } catch (const std::invalid_argument&) {
    weight = area;  // a malformed report: count pixels
  }
  RowDensity rows(area);
  for (const DeviceFrameStats& d : stats.devices)
    for (const ItemReport& r : d.items)
      rows.add(r.item, r.samples > 0 ? r.samples : weight.sum(r.item));
  if (rows.empty()) return;
  density_ = rows.density(rows.mean(1.0));
  density_shape_ = stats.shape;
  density_shape_.pixel_weight.clear();
}

}  // namespace multiray::balance
