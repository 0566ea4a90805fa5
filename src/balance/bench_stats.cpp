#include "balance/bench_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace multiray::balance {

namespace {

std::vector<double> finite(const std::vector<double>& v) {
  std::vector<double> out;
  for (double x : v)
    if (std::isfinite(x)) out.push_back(x);
  return out;
}

double median_of(std::vector<double>& v) {
  const size_t n = v.size(), mid = n / 2;
  std::nth_element(v.begin(), v.begin() + long(mid), v.end());
  if (n % 2) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + long(mid)));
}

// The q-quantile of sorted `v` (linear between order statistics).
double quantile(const std::vector<double>& v, double q) {
  const double pos = q * double(v.size() - 1);
  const size_t i = size_t(pos);
  if (i + 1 >= v.size()) return v.back();
  return v[i] + (pos - double(i)) * (v[i + 1] - v[i]);
}

std::string fmt_ratio(const Interval& r) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.2fx [%.2f, %.2f]", r.median, r.lo, r.hi);
  return buf;
}

}  // namespace

Interval bootstrap_median(const Blocks& values, const BootstrapOptions& o) {
  Blocks blocks;
  std::vector<double> all;
  for (const auto& b : values) {
    std::vector<double> f = finite(b);
    if (f.empty()) continue;
    all.insert(all.end(), f.begin(), f.end());
    blocks.push_back(std::move(f));
  }
  Interval out;
  if (all.empty()) return out;
  out.valid = true;
  out.median = median_of(all);
  std::mt19937_64 rng(o.seed);
  std::vector<double> medians, draw;
  medians.reserve(size_t(o.resamples));
  for (int r = 0; r < o.resamples; ++r) {
    draw.clear();
    for (size_t k = 0; k < blocks.size(); ++k) {
      const auto& b = blocks[std::uniform_int_distribution<size_t>(0, blocks.size() - 1)(rng)];
      std::uniform_int_distribution<size_t> pick(0, b.size() - 1);
      for (size_t i = 0; i < b.size(); ++i) draw.push_back(b[pick(rng)]);
    }
    medians.push_back(median_of(draw));
  }
  if (medians.empty()) {  // no resampling asked for: the median alone
    out.lo = out.hi = out.median;
    return out;
  }
  std::sort(medians.begin(), medians.end());
  const double tail = 0.5 * (1.0 - o.confidence);
  out.lo = std::min(out.median, quantile(medians, tail));
  out.hi = std::max(out.median, quantile(medians, 1.0 - tail));
  return out;
}

Blocks paired_ratios(const Blocks& a, const Blocks& b) {
  Blocks out(std::min(a.size(), b.size()));
  for (size_t k = 0; k < out.size(); ++k)
    for (size_t f = 0; f < std::min(a[k].size(), b[k].size()); ++f)
      if (b[k][f] > 0 && std::isfinite(a[k][f])) out[k].push_back(a[k][f] / b[k][f]);
  return out;
}

bool separated(const Interval& a, const Interval& b) {
  return a.valid && b.valid && (a.hi < b.lo || b.hi < a.lo);
}

Verdict verdict(const std::vector<std::string>& names, const std::vector<Blocks>& lanes,
                const BootstrapOptions& o) {
  Verdict v;
  for (const Blocks& b : lanes) v.medians.push_back(bootstrap_median(b, o));
  for (size_t i = 0; i < v.medians.size(); ++i)
    if (v.medians[i].valid &&
        (v.best < 0 || v.medians[i].median < v.medians[size_t(v.best)].median))
      v.best = int(i);
  v.ratios.assign(lanes.size(), Interval{});
  if (v.best < 0) {
    v.text = "no lane has a figure";
    return v;
  }
  const std::string best = names[size_t(v.best)];
  std::string slower;
  for (size_t i = 0; i < lanes.size(); ++i) {
    if (int(i) == v.best) continue;
    v.ratios[i] = bootstrap_median(paired_ratios(lanes[i], lanes[size_t(v.best)]), o);
    if (!v.ratios[i].valid) continue;
    if (v.ratios[i].lo <= 1.0)
      v.tied.push_back(int(i));
    else
      slower += (slower.empty() ? "" : ", ") + names[i] + " " + fmt_ratio(v.ratios[i]);
  }
  if (v.tied.empty()) {
    v.text = best + " is fastest";
  } else {
    v.text = best;
    for (int t : v.tied) v.text += ", " + names[size_t(t)];
    v.text += " are tied (their ratio's interval to " + best + " includes 1)";
  }
  if (!slower.empty()) v.text += "; slower: " + slower;
  return v;
}

NoiseVerdict noise_gate(const NoiseReadings& r, const NoiseLimits& limits) {
  NoiseVerdict v;
  for (size_t l = 0; l < r.lane_frame_ms.size(); ++l) {
    const Blocks& lane = r.lane_frame_ms[l];
    std::vector<double> medians;
    for (const std::vector<double>& block : lane) {
      std::vector<double> f = finite(block);
      if (!f.empty()) medians.push_back(median_of(f));
    }
    if (medians.size() < 2) continue;
    const auto [lo, hi] = std::minmax_element(medians.begin(), medians.end());
    const double range = *hi - *lo;  // before median_of reorders `medians`
    const double mid = median_of(medians);
    if (mid > 0 && range / mid > v.spread) v.spread = range / mid, v.spread_lane = int(l);
  }
  char buf[160];
  auto add = [&](const char* text) {
    v.reason += (v.reason.empty() ? "" : "; ") + std::string(text);
    v.trustworthy = false;
  };
  // fmin and fmax skip a NaN (a probe not run).
  const double low = std::fmin(r.probe_before, r.probe_after);
  const double high = std::fmax(r.probe_before, r.probe_after);
  if (low < limits.min_probe || high > limits.max_probe) {
    std::snprintf(buf, sizeof buf,
                  "contention probe %.2f before, %.2f after the run (1 = no other load; "
                  "needs %.2f..%.2f)",
                  r.probe_before, r.probe_after, limits.min_probe, limits.max_probe);
    add(buf);
  }
  if (r.steal > limits.max_steal) {
    std::snprintf(buf, sizeof buf, "the hypervisor stole %.1f%% of CPU time (limit %.1f%%)",
                  100 * r.steal, 100 * limits.max_steal);
    add(buf);
  }
  if (v.spread > limits.max_spread) {
    const size_t l = size_t(v.spread_lane);
    std::snprintf(buf, sizeof buf,
                  "%s's frame time differs by %.0f%% between repeat blocks (limit %.0f%%)",
                  l < r.lane_names.size() ? r.lane_names[l].c_str() : "a balancer", 100 * v.spread,
                  100 * limits.max_spread);
    add(buf);
  }
  return v;
}

}  // namespace multiray::balance
