#include "balance/hybrid.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "balance/line_density.h"
#include "partition/cdf_split.h"
#include "partition/scanline.h"
#include "partition/shuffled_strips.h"

namespace multiray::balance {

HybridBalancer::HybridBalancer(int device_count) : HybridBalancer(device_count, Options{}) {}

HybridBalancer::HybridBalancer(int device_count, const Options& options)
    : BalancerBase(device_count),
      opt_(options),
      speed_(size_t(device_count), 0.0),
      overhead_(size_t(device_count), 0.0),
      overhead_sum_(size_t(device_count), 0.0),
      overhead_weight_(size_t(device_count), 0.0),
      noise_sum_(size_t(device_count), 0.0),
      noise_weight_(size_t(device_count), 0.0),
      undo_sum_(size_t(device_count), 0.0),
      undo_weight_(size_t(device_count), 0.0),
      noise_count_(size_t(device_count), 0),
      pending_(size_t(device_count), 0),
      changes_(size_t(device_count), 0),
      pending_base_(size_t(device_count), 0.0),
      frame_cost_(size_t(device_count), 0.0),
      frame_seen_(size_t(device_count), false) {}

std::string HybridBalancer::spec() const {
  std::ostringstream s;
  s << "hybrid:bands=" << opt_.bands << ":taper=" << opt_.taper << ":tail=" << opt_.tail
    << ":alpha=" << opt_.alpha << ":jump=" << opt_.jump << ":gamma=" << opt_.gamma
    << ":min_chunk=" << opt_.min_chunk << ":steal=" << (opt_.steal ? 1 : 0)
    << ":overhead=" << opt_.overhead << ":detect=" << (opt_.detect_noise ? "noise" : "fixed")
    << ":z=" << opt_.z << ":frame=" << (opt_.frame_cost ? 1 : 0);
  return s.str();
}

void HybridBalancer::reset_cost(const FrameShape& shape) {
  cost_.assign(size_t(shape.views) * size_t(shape.height), 1.0);
  cost_shape_ = FrameShape{shape.width, shape.height, shape.views, {}};
}

double HybridBalancer::noise(size_t i) const {
  return noise_weight_[i] > 0 ? std::sqrt(noise_sum_[i] / noise_weight_[i]) : 0.0;
}

std::vector<double> HybridBalancer::noise() const {
  std::vector<double> sigma(speed_.size());
  for (size_t i = 0; i < sigma.size(); ++i) sigma[i] = noise(i);
  return sigma;
}

bool HybridBalancer::jumps(size_t i, double m) const {
  const double s = speed_[i];
  if (!opt_.detect_noise || noise_count_[i] < kMinHistory) return std::abs(m / s - 1) > opt_.jump;
  return std::abs(std::log(m / s)) > std::max(opt_.z * noise(i), kNoiseFloor);
}

void HybridBalancer::take_speed(size_t i, double m) {
  double& s = speed_[i];
  if (!(s > 0)) {  // the first measurement
    s = m;
    return;
  }
  bool change = jumps(i, m);
  int beyond = 0;  // the side of a measurement beyond the confirmation bound
  if (opt_.detect_noise && noise_count_[i] >= kMinHistory) {
    const double bound = std::max(kConfirmSigmas * noise(i), kNoiseFloor);
    const double r = std::log(m / s), r0 = std::log(m / pending_base_[i]);
    if (!change && pending_[i] != 0 && std::abs(r0) > bound && (r0 > 0 ? 1 : -1) == pending_[i]) {
      // The second measurement in a row beyond the bound on the same side of the estimate
      // both were made against: a change that began with the first, which therefore
      // leaves the noise history again.
      change = true;
      noise_sum_[i] = undo_sum_[i], noise_weight_[i] = undo_weight_[i], --noise_count_[i];
    }
    if (std::abs(r) > bound) beyond = r > 0 ? 1 : -1;
  }
  if (change) {
    s = m;
    pending_[i] = 0;
    ++changes_[i];
    return;
  }
  if (opt_.detect_noise) {
    const double r = std::log(m / s);
    undo_sum_[i] = noise_sum_[i], undo_weight_[i] = noise_weight_[i];
    noise_sum_[i] = (1 - kNoiseWeight) * noise_sum_[i] + kNoiseWeight * r * r;
    noise_weight_[i] = (1 - kNoiseWeight) * noise_weight_[i] + kNoiseWeight;
    ++noise_count_[i];
    pending_[i] = beyond;
    pending_base_[i] = s;
  }
  s = (1 - opt_.alpha) * s + opt_.alpha * m;
}

void HybridBalancer::take_frame_cost(size_t i, const DeviceFrameStats& d) {
  if (!opt_.frame_cost || d.items.empty()) return;
  double items = 0;
  for (const ItemReport& r : d.items) {
    if (!valid_time(r.time_ms)) return;  // an unusable item time: no gap to measure
    items += r.time_ms;
  }
  const double gap = std::max(d.time_ms - items, 0.0);
  if (!std::isfinite(gap)) return;
  double& f = frame_cost_[i];
  f = frame_seen_[i] ? (1 - kFrameCostWeight) * f + kFrameCostWeight * gap : gap;
  frame_seen_[i] = true;
}

std::vector<double> HybridBalancer::planning_speeds() const {
  // Devices not measured yet get the mean measured speed (all equal if none is).
  double sum = 0;
  int known = 0;
  for (int i = 0; i < device_count(); ++i)
    if (alive(i) && speed_[size_t(i)] > 0) sum += speed_[size_t(i)], ++known;
  const double guess = known > 0 ? sum / known : 1.0;
  std::vector<double> s(speed_.size(), 0.0);
  for (int i = 0; i < device_count(); ++i)
    if (alive(i)) s[size_t(i)] = speed_[size_t(i)] > 0 ? speed_[size_t(i)] : guess;
  return s;
}

std::vector<double> HybridBalancer::overhead_shares(const std::vector<double>& speed,
                                                    const std::vector<double>& items,
                                                    double total) const {
  // n_i = s_i·(T − f_i − k_i·o_i), at least s_i·kMinWork·T, and Σn_i = total: the work is
  // increasing in T, so T is found by bisection.
  constexpr double kMinWork = 0.05;
  const size_t n = speed.size();
  double speed_sum = 0, fixed_max = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!alive(int(i)) || !(speed[i] > 0)) continue;
    speed_sum += speed[i];
    fixed_max = std::max(fixed_max, frame_cost_[i] + items[i] * overhead_[i]);
  }
  auto work = [&](double t, size_t i) {
    if (!alive(int(i)) || !(speed[i] > 0)) return 0.0;
    return speed[i] * std::max(t - frame_cost_[i] - items[i] * overhead_[i], kMinWork * t);
  };
  const std::vector<double> plain = sanitize(speed, even());
  if (!(speed_sum > 0) || !(total > 0) || !std::isfinite(total + fixed_max)) return plain;
  double lo = 0, hi = total / speed_sum + fixed_max;
  for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += work(mid, i);
    (sum < total ? lo : hi) = mid;
  }
  std::vector<double> share(n, 0.0);
  for (size_t i = 0; i < n; ++i) share[i] = work(hi, i);
  return sanitize(share, plain);
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
    const std::vector<double>& shares, const std::vector<double>& floor,
    const std::vector<size_t>& order) const {
  const size_t n = shares.size(), m = size_t(opt_.bands);
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
        double c = std::min(piece, std::max(floor[i], left[i] * (1 - opt_.taper)));
        if (piece - c < 0.5 * floor[i] || ++count[i] >= kMaxChunks) c = piece;
        chunks[band][i].push_back(c);
        piece -= c;
        left[i] -= c;
      }
    }
  return chunks;
}

void HybridBalancer::snap_to_rows(std::vector<int64_t>& cuts, const std::vector<size_t>& owner,
                                  const std::vector<double>& row_cost, int width,
                                  const std::vector<double>& shares,
                                  const std::vector<double>& speed) const {
  // err[i]: cost device i gained by the moves so far. Each move takes the side that keeps
  // err² of the two devices it changes smallest, so every device stays within about one
  // move of its share.
  double total = 0;
  for (double c : row_cost) total += std::max(0.0, c);
  std::vector<double> err(speed.size(), 0.0);
  for (size_t j = 1; j + 1 < cuts.size(); ++j) {
    const int64_t c = cuts[j], row = c / width, down = row * width, up = down + width;
    if (c == down || size_t(row) >= row_cost.size()) continue;
    const size_t a = owner[j - 1], b = owner[j];  // the chunks before and after the cut
    const double saved = overhead_[a] + overhead_[b];
    if (!(saved > 0)) continue;
    // A move is worth it when its pixels take less time than the fixed costs it saves,
    // or when it is within kSnapShare of either device's share (the error does not add
    // up over the moves).
    const double limit = std::max(saved * std::min(speed[a], speed[b]),
                                  kSnapShare * std::min(shares[a], shares[b]) * total);
    const double per_pixel = std::max(0.0, row_cost[size_t(row)]) / width;
    double best = std::numeric_limits<double>::infinity();
    int64_t to = c;
    for (const int64_t target : {down, up}) {
      if (target < cuts[j - 1] || target > cuts[j + 1]) continue;  // keep the cuts in order
      const double moved = double(target - c) * per_pixel;         // a gains, b loses
      if (!(std::abs(moved) <= limit)) continue;
      const double score =
          a == b ? std::abs(moved) : std::pow(err[a] + moved, 2) + std::pow(err[b] - moved, 2);
      if (score < best) best = score, to = target;
    }
    if (to == c) continue;
    const double moved = double(to - c) * per_pixel;
    err[a] += moved;
    err[b] -= moved;
    cuts[j] = to;
  }
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

std::vector<std::vector<WorkItem>> HybridBalancer::lay_out(
    const FrameShape& shape, const std::vector<double>& row_cost,
    const std::vector<double>& shares, const std::vector<double>& speed) const {
  // The smallest chunk: `tail` of the slowest device's share, i.e. what it renders in
  // `tail` of the ideal frame time; for a device with a fixed cost per item, at least
  // what makes that cost `overhead` of the chunk's time, but no more than 0.4 of a piece
  // (so its last piece is still cut in chunks of different sizes, which the fit of the
  // fixed cost needs).
  const size_t n = shares.size(), m = size_t(opt_.bands);
  double slowest = 1, total = 0;
  for (double sh : shares)
    if (sh > 0) slowest = std::min(slowest, sh);
  for (double c : row_cost) total += c;
  std::vector<double> floor(n, std::max(opt_.tail * slowest, 1e-9));
  if (opt_.detect_noise)  // a noisy device's floor grows by its noise
    for (size_t i = 0; i < n; ++i)
      if (noise_count_[i] >= kMinHistory && !(overhead_[i] > 0)) {
        const double f = (opt_.tail + noise(i) / kNoiseChunks) * slowest;
        if (std::isfinite(f))
          floor[i] = std::max(floor[i], std::min(f, 0.4 * shares[i] / double(m)));
      }
  const bool model = opt_.overhead > 0 && total > 0 && std::isfinite(total);
  if (model)
    for (size_t i = 0; i < n; ++i) {
      const double f = overhead_[i] * speed[i] * (1 - opt_.overhead) / opt_.overhead / total;
      if (std::isfinite(f))
        floor[i] = std::max(floor[i], std::min(f, 0.4 * shares[i] / double(m)));
    }

  // Lay the pieces out band by band (device order rotated by the band index), cut them
  // all with one CDF search, then list each device's pieces in rendering order.
  const std::vector<size_t> order = band_order();
  const auto chunks = chunk_costs(shares, floor, order);
  std::vector<double> flat;
  std::vector<size_t> first;  // index in `flat` of the first chunk of each laid-out piece
  std::vector<size_t> owner;  // device of each chunk in `flat`
  for (size_t b = 0; b < m; ++b)
    for (size_t k = 0; k < n; ++k) {
      first.push_back(flat.size());
      const auto& piece = chunks[b][(k + b) % n];
      flat.insert(flat.end(), piece.begin(), piece.end());
      owner.insert(owner.end(), piece.size(), (k + b) % n);
    }
  first.push_back(flat.size());
  std::vector<int64_t> cuts = cdf_cuts(row_cost, shape.width, flat);
  if (model) snap_to_rows(cuts, owner, row_cost, shape.width, shares, speed);
  std::vector<std::vector<std::vector<WorkItem>>> items(n, std::vector<std::vector<WorkItem>>(m));
  for (size_t b = 0; b < m; ++b)
    for (size_t k = 0; k < n; ++k) {
      const size_t p = b * n + k;
      const std::vector<int64_t> mine(cuts.begin() + long(first[p]),
                                      cuts.begin() + long(first[p + 1]) + 1);
      append_chunks(shape, mine, items[(k + b) % n][b]);
    }
  std::vector<std::vector<WorkItem>> assigned(n);
  for (size_t i = 0; i < n; ++i)
    for (size_t b : order)
      assigned[i].insert(assigned[i].end(), items[i][b].begin(), items[i][b].end());
  return assigned;
}

Plan HybridBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0 || shape.pixels() == 0) return empty_plan();
  if (!cost_shape_.same_size(shape)) reset_cost(shape);

  const WeightMap base(shape.width, shape.height, shape.views, shape.pixel_weight);
  std::vector<double> row_cost = flat_row_weights(base);
  double total = 0;
  for (size_t c = 0; c < row_cost.size(); ++c) total += row_cost[c] *= cost_[c];

  const std::vector<double> speed = planning_speeds();
  Plan plan;
  plan.ratios = sanitize(speed, even());
  plan.steal = opt_.steal;
  plan.assigned = lay_out(shape, row_cost, plan.ratios, speed);
  bool per_item = false, per_frame = false;
  for (int i = 0; i < device_count(); ++i) {
    per_item |= alive(i) && overhead_[size_t(i)] > 0;
    per_frame |= alive(i) && frame_cost_[size_t(i)] > 0;
  }
  per_item &= opt_.overhead > 0;
  if (per_item || per_frame) {
    // Count each device's items on the layout by speeds, split so that work plus fixed
    // costs take every device the same time, and lay the frame out again.
    std::vector<double> items(plan.assigned.size(), 0.0);
    if (per_item)
      for (size_t i = 0; i < items.size(); ++i) items[i] = double(plan.assigned[i].size());
    plan.ratios = overhead_shares(speed, items, total);
    plan.assigned = lay_out(shape, row_cost, plan.ratios, speed);
  }
  return plan;
}

namespace {

// Intercept of the least-squares line t = o + c/s through (cost, time) pairs, weighted by
// 1/cost, and its variance (from the residuals). False when there are fewer than 3 usable
// pairs, the costs differ by less than 2x, or the slope is not positive.
bool fixed_cost_fit(const std::vector<std::pair<double, double>>& points, double& intercept,
                    double& variance) {
  double w = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, lo = std::numeric_limits<double>::infinity(),
         hi = 0;
  int count = 0;
  auto usable = [](double c, double t) { return c > 0 && std::isfinite(c) && valid_time(t); };
  for (const auto& [c, t] : points) {
    if (!usable(c, t)) continue;
    const double wi = 1 / c;
    w += wi, sx += wi * c, sy += wi * t, sxx += wi * c * c, sxy += wi * c * t;
    lo = std::min(lo, c), hi = std::max(hi, c), ++count;
  }
  if (count < 3 || !(hi >= 2 * lo)) return false;
  const double det = w * sxx - sx * sx;
  if (!(det > 0) || !std::isfinite(det)) return false;
  const double slope = (w * sxy - sx * sy) / det;
  if (!(slope > 0) || !std::isfinite(slope)) return false;
  intercept = (sy - slope * sx) / w;
  double residual = 0;
  for (const auto& [c, t] : points)
    if (usable(c, t)) residual += std::pow(t - intercept - slope * c, 2) / c;
  variance = residual / (count - 2) * sxx / det;
  return std::isfinite(intercept) && std::isfinite(variance);
}

}  // namespace

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

  LineDensity observed(base);
  std::vector<std::pair<double, double>> points;  // (model cost, time) of each item
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms)) continue;
    double work = 0;
    points.clear();
    for (const ItemReport& r : d->items) {
      points.push_back({model_cost(r.item), r.time_ms});
      work += points.back().first;
    }
    if (d->items.empty()) work = work_done(*d);  // no item reports: assume mean cost 1
    if (!(work > 0) || !std::isfinite(work)) continue;
    // The fixed cost per item, and the device's time net of it. Each frame's fit counts by
    // its precision (1/variance; a fit on a few items under outside load is worth little
    // next to one on many), older fits fading by kOverheadMemory a frame. A speed that changed
    // during the frame makes the last (small) items look dear, as a fixed cost would: the
    // fit is only taken when the speed measured with the current fixed cost is no jump.
    take_frame_cost(size_t(i), *d);
    const double items = double(d->items.size());
    const double f = frame_cost_[size_t(i)];
    double& o = overhead_[size_t(i)];
    const double s = speed_[size_t(i)];
    const double mean_item = (d->time_ms - f) / items;
    // (With `jump` in either mode: this gate is for gross changes inside the frame. The
    // noise rule would also shut out the frames whose speed moves by a few percent because
    // o_i is still being learnt, and o_i would never be.)
    const bool steady =
        !(s > 0) || std::abs(work / std::max(d->time_ms - f - items * o, 0.5 * d->time_ms) / s -
                             1) <= opt_.jump;
    double fit = 0, variance = 0;
    bool timed = false;  // some item has a usable time
    for (const ItemReport& r : d->items) timed |= valid_time(r.time_ms);
    if (opt_.overhead > 0 && own_shape && timed) {
      double& sum = overhead_sum_[size_t(i)];
      double& weights = overhead_weight_[size_t(i)];
      sum *= kOverheadMemory, weights *= kOverheadMemory;  // earlier fits age, fit or not
      if (steady && fixed_cost_fit(points, fit, variance)) {
        const double weight = 1 / (variance + std::pow(1e-3 * mean_item, 2));
        sum += weight * std::clamp(fit, -0.5 * mean_item, 0.5 * mean_item);
        weights += weight;
      }
      // Two standard errors below the mean: errors in the model costs bias the intercept
      // upwards, so only what the frames show clearly counts (and aged evidence fades).
      const double clear = sum / weights - 2 / std::sqrt(weights);
      o = std::isfinite(clear) ? std::clamp(clear, 0.0, 0.5 * mean_item) : 0.0;
    }
    const double net = std::max(d->time_ms - f - items * o, 0.5 * d->time_ms);
    const double measured = work / net;
    take_speed(size_t(i), measured);
    // Each item's time net of the fixed cost, as a share of the device's work: its
    // observed cost (so emulated idle, if the engine reports it only per frame, is
    // spread over the items).
    if (!own_shape) continue;
    double item_time = 0;
    for (const ItemReport& r : d->items)
      if (valid_time(r.time_ms)) item_time += std::max(r.time_ms - o, 0.0);
    if (!(item_time > 0)) continue;
    const double scale = net / item_time * measured;
    for (const ItemReport& r : d->items)
      if (valid_time(r.time_ms)) observed.add(r.item, std::max(r.time_ms - o, 0.0) * scale);
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
