#include "balance/hybrid.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "balance/row_density.h"
#include "partition/cdf_split.h"
#include "partition/scanline.h"
#include "partition/shuffled_strips.h"

namespace multiray::balance {

HybridBalancer::HybridBalancer(int device_count) : HybridBalancer(device_count, Options{}) {}

HybridBalancer::HybridBalancer(int device_count, const Options& options)
    : BalancerBase(device_count), opt_(options), speed_(size_t(device_count), 0.0) {}

std::string HybridBalancer::spec() const {
  std::ostringstream s;
  s << "hybrid:bands=" << opt_.bands << ":taper=" << opt_.taper << ":tail=" << opt_.tail
    << ":alpha=" << opt_.alpha << ":jump=" << opt_.jump << ":gamma=" << opt_.gamma
    << ":min_chunk=" << opt_.min_chunk << ":steal=" << (opt_.steal ? 1 : 0);
  return s.str();
}

void HybridBalancer::reset_cost(const FrameShape& shape) {
  cost_.assign(size_t(shape.views) * size_t(shape.height), 1.0);
  cost_shape_ = FrameShape{shape.width, shape.height, shape.views, {}};
}

std::vector<double> HybridBalancer::shares() const {
  // Devices not measured yet get the mean measured speed (all equal if none is).
  double sum = 0;
  int known = 0;
  for (int i = 0; i < device_count(); ++i)
    if (alive(i) && speed_[size_t(i)] > 0) sum += speed_[size_t(i)], ++known;
  const double guess = known > 0 ? sum / known : 1.0;
  std::vector<double> s(speed_.size(), 0.0);
  for (int i = 0; i < device_count(); ++i)
    if (alive(i)) s[size_t(i)] = speed_[size_t(i)] > 0 ? speed_[size_t(i)] : guess;
  return sanitize(s, even());
}

std::vector<size_t> HybridBalancer::band_order() const {
  // Van der Corput order of 0..bands-1 (bit reversal, skipping values >= bands): any
  // prefix, and any suffix, of it is spread over the whole frame.
  const size_t m = size_t(opt_.bands);
  int bits = 0;
  while ((size_t(1) << bits) < m) ++bits;
  std::vector<size_t> order;
  for (uint32_t j = 0; j < (1u << bits); ++j)
    if (bit_reverse(j, bits) < m) order.push_back(bit_reverse(j, bits));
  return order;
}

std::vector<std::vector<std::vector<double>>> HybridBalancer::chunk_costs(
    const std::vector<double>& shares, const std::vector<size_t>& order) const {
  const size_t n = shares.size(), m = size_t(opt_.bands);
  // The smallest chunk: `tail` of the slowest device's share, i.e. what it renders in
  // `tail` of the ideal frame time.
  double slowest = 1;
  for (double sh : shares)
    if (sh > 0) slowest = std::min(slowest, sh);
  const double floor = std::max(opt_.tail * slowest, 1e-9);

  // chunks[band][device]: cost fractions of the chunks of that piece, front to back. Sizes
  // follow the order the device will render its pieces in, so its last pieces get the
  // small chunks.
  std::vector<std::vector<std::vector<double>>> chunks(m, std::vector<std::vector<double>>(n));
  std::vector<double> left = shares;  // of each device's share, not yet cut
  std::vector<size_t> count(n, 0);
  for (size_t band : order)
    for (size_t i = 0; i < n; ++i) {
      double piece = shares[i] / double(m);
      while (piece > 0) {
        double c = std::min(piece, std::max(floor, left[i] * (1 - opt_.taper)));
        if (piece - c < 0.5 * floor || ++count[i] >= kMaxChunks) c = piece;
        chunks[band][i].push_back(c);
        piece -= c;
        left[i] -= c;
      }
    }
  return chunks;
}

void HybridBalancer::append_chunks(const FrameShape& shape, const std::vector<int64_t>& cuts,
                                   std::vector<WorkItem>& out) const {
  int64_t begin = cuts.front(), last_begin = -1, last_end = -1;
  auto emit = [&](int64_t b, int64_t e) {
    if (last_end >= 0) append_flat_range(shape.width, shape.height, last_begin, last_end, out);
    last_begin = b, last_end = e;
  };
  for (size_t j = 1; j < cuts.size(); ++j)
    if (cuts[j] - begin >= opt_.min_chunk) emit(begin, cuts[j]), begin = cuts[j];
  if (cuts.back() > begin) {  // a short tail: merge it into the chunk before, if any
    if (last_end >= 0)
      last_end = cuts.back();
    else
      last_begin = begin, last_end = cuts.back();
  }
  if (last_end >= 0) append_flat_range(shape.width, shape.height, last_begin, last_end, out);
}

Plan HybridBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0 || shape.pixels() == 0) return empty_plan();
  if (!cost_shape_.same_size(shape)) reset_cost(shape);

  const WeightMap base(shape.width, shape.height, shape.views, shape.pixel_weight);
  std::vector<double> row_cost = flat_row_weights(base);
  for (size_t c = 0; c < row_cost.size(); ++c) row_cost[c] *= cost_[c];

  Plan plan;
  plan.ratios = shares();
  plan.steal = opt_.steal;
  plan.assigned.resize(size_t(device_count()));

  // Lay the pieces out band by band (device order rotated by the band index), cut them
  // all with one CDF search, then list each device's pieces in rendering order.
  const size_t n = plan.assigned.size(), m = size_t(opt_.bands);
  const std::vector<size_t> order = band_order();
  const auto chunks = chunk_costs(plan.ratios, order);
  std::vector<double> flat;
  std::vector<size_t> first;  // index in `flat` of the first chunk of each laid-out piece
  for (size_t b = 0; b < m; ++b)
    for (size_t k = 0; k < n; ++k) {
      first.push_back(flat.size());
      const auto& piece = chunks[b][(k + b) % n];
      flat.insert(flat.end(), piece.begin(), piece.end());
    }
  first.push_back(flat.size());
  const std::vector<int64_t> cuts = cdf_cuts(row_cost, shape.width, flat);
  std::vector<std::vector<std::vector<WorkItem>>> items(n, std::vector<std::vector<WorkItem>>(m));
  for (size_t b = 0; b < m; ++b)
    for (size_t k = 0; k < n; ++k) {
      const size_t p = b * n + k;
      const std::vector<int64_t> mine(cuts.begin() + long(first[p]),
                                      cuts.begin() + long(first[p + 1]) + 1);
      append_chunks(shape, mine, items[(k + b) % n][b]);
    }
  for (size_t i = 0; i < n; ++i)
    for (size_t b : order)
      plan.assigned[i].insert(plan.assigned[i].end(), items[i][b].begin(), items[i][b].end());
  return plan;
}

void HybridBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  const FrameShape& shape = stats.shape;
  if (alive_count() == 0 || shape.pixels() == 0) return;
  // A report for another size than the last plan (a foreign or stale report) still
  // measures speeds, at mean cost 1, but teaches nothing about this frame's rows.
  const bool own_shape = cost_shape_.same_size(shape);
  WeightMap base;
  try {
    base = WeightMap(shape.width, shape.height, shape.views, shape.pixel_weight);
  } catch (const std::invalid_argument&) {
    base = WeightMap(shape.width, shape.height, shape.views, {});
  }
  // Model cost of an item: Σ over its rows of base weight × k(row).
  auto model_cost = [&](const WorkItem& item) {
    if (!own_shape) return base.sum(item);
    double c = 0;
    if (item.view < 0 || item.view >= shape.views) return c;
    for (int y = std::max(item.rect.y0, 0); y < std::min(item.rect.y1, shape.height); ++y)
      c += base.sum(WorkItem{Rect{item.rect.x0, y, item.rect.x1, y + 1}, item.view}) *
           cost_[size_t(item.view) * size_t(shape.height) + size_t(y)];
    return c;
  };

  RowDensity observed(base);
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms)) continue;
    double work = 0, item_time = 0;
    for (const ItemReport& r : d->items) {
      work += model_cost(r.item);
      if (valid_time(r.time_ms)) item_time += r.time_ms;
    }
    if (d->items.empty()) work = work_done(*d);  // no item reports: assume mean cost 1
    if (!(work > 0) || !std::isfinite(work)) continue;
    const double measured = work / d->time_ms;
    double& s = speed_[size_t(i)];
    if (!(s > 0) || std::abs(measured / s - 1) > opt_.jump)
      s = measured;
    else
      s = (1 - opt_.alpha) * s + opt_.alpha * measured;
    // Item times rescaled to add up to the device's time (so emulated idle time, if the
    // engine reports it only per frame, is spread over the items), then into cost units.
    if (!(item_time > 0) || !own_shape) continue;
    const double scale = d->time_ms / item_time * measured;
    for (const ItemReport& r : d->items)
      if (valid_time(r.time_ms)) observed.add(r.item, r.time_ms * scale);
  }
  if (observed.empty()) return;

  const std::vector<double> fresh = observed.density(std::numeric_limits<double>::quiet_NaN());
  const std::vector<double> row_base = flat_row_weights(base);
  double weighted = 0, base_sum = 0;
  for (size_t c = 0; c < cost_.size(); ++c) {
    if (std::isfinite(fresh[c])) cost_[c] = (1 - opt_.gamma) * cost_[c] + opt_.gamma * fresh[c];
    weighted += row_base[c] * cost_[c];
    base_sum += row_base[c];
  }
  // Keep k at mean 1 (costs and speeds scale together, so the plan is unchanged).
  const double f = weighted / base_sum;
  if (!(f > 0) || !std::isfinite(f)) return;
  // Clamped so one absurd report cannot make a row free or infinitely dear.
  for (double& k : cost_) k = std::clamp(k / f, 1e-3, 1e3);
  for (double& s : speed_) s /= f;
}

}  // namespace multiray::balance
