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
      frame_seen_(size_t(device_count), false),
      part_(device_count, ParticipationTracker::Options{options.leave, options.probe, 0.03}),
      probing_(size_t(device_count), false) {}

std::string HybridBalancer::spec() const {
  std::ostringstream s;
  s << "hybrid:bands=" << opt_.bands << ":taper=" << opt_.taper << ":tail=" << opt_.tail
    << ":alpha=" << opt_.alpha << ":jump=" << opt_.jump << ":gamma=" << opt_.gamma
    << ":min_chunk=" << opt_.min_chunk << ":steal=" << (opt_.steal ? 1 : 0)
    << ":overhead=" << opt_.overhead << ":detect=" << (opt_.detect_noise ? "noise" : "fixed")
    << ":z=" << opt_.z << ":frame=" << (opt_.frame_cost ? 1 : 0)
    << ":leave=" << (opt_.leave ? 1 : 0) << ":probe=" << opt_.probe;
  return s.str();
}

void HybridBalancer::reset_cost(const FrameShape& shape) {
  cost_.assign(size_t(shape.views) * size_t(shape.height), 1.0);
  cost_shape_ = FrameShape{shape.width, shape.height, shape.views, {}};
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

  // Which devices take part (participation.h); the plan is made for them alone, then
  // probed devices get their small shares.
  if (!cost_shape_.same_size(shape)) part_.changed(false);
  std::vector<bool> alive_now(static_cast<size_t>(device_count()), false);
  for (int i = 0; i < device_count(); ++i) alive_now[size_t(i)] = alive(i);
  std::vector<double> speed = planning_speeds();
  const ParticipationTracker::Decision part = part_.decide(alive_now, total, speed);
  bool probes = false;
  for (size_t i = 0; i < speed.size(); ++i) {
    probing_[i] = part.probe[i] > 0;
    probes |= probing_[i];
    if (part.rest[i] || probing_[i]) speed[i] = 0;
  }
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
  if (probes) add_probes(plan, part.probe, shape, row_cost, speed);
  plan.resting = part.rest;
  plan.rest_reason = part.reason;
  plan.models = part.models;
  // A device whose fixed cost is a visible part of the frame pays it again for each item
  // it steals, mostly after the owner would have finished it: it does not steal.
  plan.no_steal.assign(plan.assigned.size(), false);
  for (size_t i = 0; i < plan.no_steal.size(); ++i)
    plan.no_steal[i] =
        part.models[i].determined && part.models[i].fixed_ms > kNoStealFixed * part.predicted_ms;
  return plan;
}

void HybridBalancer::add_probes(Plan& plan, const std::vector<double>& probe,
                                const FrameShape& shape, const std::vector<double>& row_cost,
                                const std::vector<double>& speed) const {
  double probed = 0;
  for (double p : probe) probed += p;
  if (!(probed > 0 && probed < 1)) return;
  for (size_t i = 0; i < plan.ratios.size(); ++i)
    plan.ratios[i] = probe[i] > 0 ? probe[i] : plan.ratios[i] * (1 - probed);
  plan.assigned = lay_out(shape, row_cost, plan.ratios, speed);
}

}  // namespace multiray::balance
