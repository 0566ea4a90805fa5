#include "app/bench_summary.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "balance/stats.h"

namespace multiray::app {

double interpolate_ideal(const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                         int frame) {
  if (frame <= sampled.front()) return ideal_ms.front();
  if (frame >= sampled.back()) return ideal_ms.back();
  size_t k = 0;
  while (sampled[k + 1] < frame) ++k;
  const double t = double(frame - sampled[k]) / double(sampled[k + 1] - sampled[k]);
  return ideal_ms[k] * (1 - t) + ideal_ms[k + 1] * t;
}

double mean_ideal_ms(const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                     int from, int to) {
  if (from >= to || sampled.empty()) return 0;
  double sum = 0;
  for (int f = from; f < to; ++f) sum += interpolate_ideal(sampled, ideal_ms, f);
  return sum / double(to - from);
}

int default_warmup(int frames) { return std::clamp(frames / 4, 0, 10); }

RunSummary summarize(const std::vector<FrameRecord>& recs, int warmup,
                     const std::vector<int>& sampled, const std::vector<double>& ideal_ms,
                     int perturb_frame) {
  RunSummary sum;
  int counted = 0;
  for (const auto& r : recs)
    if (r.frame >= warmup) {
      sum.mean_frame_ms += r.frame_ms, sum.mean_imbalance += r.imbalance;
      sum.mean_deviation += r.deviation, ++counted;
    }
  if (counted > 0)
    sum.mean_frame_ms /= counted, sum.mean_imbalance /= counted, sum.mean_deviation /= counted;
  // Efficiency over all frames >= warm-up: the ideal of a frame between two sampled ones
  // is interpolated linearly (frame cost changes smoothly along a camera path; timing the
  // devices alone on every frame would cost more than the run itself). The ideal is timed
  // at full quality, so frames rendered at another (frame-time targeting) are left out.
  double ideal_sum = 0, actual_sum = 0;
  int full_frames = 0;
  for (const auto& r : recs) {
    const bool full_quality =
        r.quality.image_scale == 1 && r.quality.step_scale == 1 && r.first_pass_ms == 0;
    if (r.frame < warmup || sampled.empty() || !full_quality) continue;
    actual_sum += r.frame_ms;
    ideal_sum += interpolate_ideal(sampled, ideal_ms, r.frame);
    ++full_frames;
  }
  sum.efficiency = actual_sum > 0 ? ideal_sum / actual_sum : 0.0;
  sum.ideal_ms = full_frames > 0 ? ideal_sum / full_frames : 0.0;
  if (perturb_frame >= 0) {
    std::vector<double> lambda;
    for (const auto& r : recs) lambda.push_back(r.imbalance);
    const int recovered = balance::recovered_from(lambda, perturb_frame);
    if (recovered >= 0) sum.recovery_frames = recovered - perturb_frame;
  }
  sum.rebalances = count_rebalances(recs);
  return sum;
}

int count_rebalances(const std::vector<FrameRecord>& recs) {
  int changes = 0;
  for (size_t f = 1; f < recs.size(); ++f) {
    const auto& now = recs[f].devices;
    const auto& before = recs[f - 1].devices;
    bool changed = now.size() != before.size();
    for (size_t i = 0; !changed && i < now.size(); ++i)
      changed = std::abs(now[i].planned_share - before[i].planned_share) > 1e-9;
    changes += changed ? 1 : 0;
  }
  return changes;
}

void add_speedups(const std::vector<std::string>& specs, std::vector<RunSummary>& summaries) {
  double uniform_ms = 0;
  for (size_t k = 0; k < specs.size(); ++k)
    if (specs[k].rfind("uniform", 0) == 0) uniform_ms = summaries[k].mean_frame_ms;
  for (RunSummary& s : summaries)
    s.speedup = uniform_ms > 0 && s.mean_frame_ms > 0 ? uniform_ms / s.mean_frame_ms : 0.0;
}

std::string mismatch_summary(const std::vector<std::string>& lanes,
                             const std::vector<std::vector<int>>& mismatched) {
  std::string out;
  for (size_t k = 0; k < mismatched.size(); ++k)
    if (!mismatched[k].empty())
      out += fmt::format("{}{}: {} frame(s), first {}", out.empty() ? "" : "; ", lanes.at(k),
                         mismatched[k].size(), mismatched[k].front());
  return out;
}

void print_table(const std::vector<std::string>& specs, const std::vector<RunSummary>& summaries) {
  size_t width = 14;  // the longest label, so specs and lane names are never cut
  for (const std::string& spec : specs) width = std::max(width, spec.size());
  fmt::print("\n{:<{}} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "balancer", width, "frame ms",
             "imbalance", "deviation", "efficiency", "speedup", "recovery");
  for (size_t k = 0; k < specs.size(); ++k) {
    const RunSummary& s = summaries[k];
    fmt::print("{:<{}} {:>10.1f} {:>9.1f}% {:>9.1f}% {:>10} {:>9} {:>9}\n", specs[k], width,
               s.mean_frame_ms, 100 * s.mean_imbalance, 100 * s.mean_deviation,
               s.efficiency > 0 ? fmt::format("{:.3f}", s.efficiency) : "-",
               s.speedup > 0 ? fmt::format("{:.2f}x", s.speedup) : "-",
               s.recovery_frames >= 0 ? std::to_string(s.recovery_frames) : "-");
  }
}

nlohmann::json summary_to_json(const RunSummary& s, int warmup, const std::vector<int>& sampled) {
  return {{"from_frame", warmup},
          {"mean_frame_ms", s.mean_frame_ms},
          {"mean_imbalance", s.mean_imbalance},
          {"mean_deviation", s.mean_deviation},
          {"ideal_ms", s.ideal_ms > 0 ? nlohmann::json(s.ideal_ms) : nlohmann::json()},
          {"ideal_frames", sampled},
          {"efficiency", s.efficiency > 0 ? nlohmann::json(s.efficiency) : nlohmann::json()},
          {"speedup_vs_uniform", s.speedup > 0 ? nlohmann::json(s.speedup) : nlohmann::json()},
          {"recovery_frames", s.recovery_frames},
          {"rebalances", s.rebalances}};
}

}  // namespace multiray::app
