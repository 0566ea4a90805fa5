#include "study/bench_summary.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/core.h>

#include "balance/stats.h"
#include "core/console.h"

namespace multiray::study {

double interpolate_ideal(const std::vector<int>& sampled, const std::vector<double>& ms,
                         int frame) {
  if (frame <= sampled.front()) return ms.front();
  if (frame >= sampled.back()) return ms.back();
  size_t k = 0;
  while (sampled[k + 1] < frame) ++k;
  const double t = double(frame - sampled[k]) / double(sampled[k + 1] - sampled[k]);
  return ms[k] * (1 - t) + ms[k + 1] * t;
}

std::vector<double> alone_at(const std::vector<IdealSample>& ideal, int frame) {
  std::vector<double> out;
  if (ideal.empty()) return out;
  std::vector<int> sampled;
  for (const IdealSample& i : ideal) sampled.push_back(i.frame);
  for (size_t d = 0; d < ideal.front().device_alone_ms.size(); ++d) {
    std::vector<double> ms;
    for (const IdealSample& i : ideal) ms.push_back(i.device_alone_ms.at(d));
    out.push_back(interpolate_ideal(sampled, ms, frame));
  }
  return out;
}

double ideal_at(const std::vector<IdealSample>& ideal, int frame) {
  double speed = 0;
  for (double ms : alone_at(ideal, frame)) speed += ms > 0 ? 1.0 / ms : 0.0;
  return speed > 0 ? 1.0 / speed : 0.0;
}

double mean_ideal_ms(const std::vector<IdealSample>& ideal, int from, int to) {
  if (from >= to || ideal.empty()) return 0;
  double sum = 0;
  for (int f = from; f < to; ++f) sum += ideal_at(ideal, f);
  return sum / double(to - from);
}

double host_ms(const FrameRecord& r) {
  return r.plan_ms + r.gather_ms + r.update_ms + r.advise_ms + r.learn_ms + r.first_pass_ms +
         r.denoise_ms;
}

double frame_total_ms(const FrameRecord& r) { return r.frame_ms + host_ms(r) - r.first_pass_ms; }

balance::Breakdown frame_breakdown(const FrameRecord& r, const std::vector<IdealSample>& ideal) {
  const std::vector<double> alone = alone_at(ideal, r.frame);
  if (alone.empty() || (!r.devices.empty() && r.devices.size() != alone.size())) return {};
  std::vector<balance::DeviceTiming> d(alone.size());
  for (size_t i = 0; i < d.size(); ++i) {
    d[i].alone_ms = alone[i];
    if (i < r.devices.size() && r.devices[i].alive) {
      d[i].time_ms = r.devices[i].time_ms;
      d[i].stolen_ms = r.devices[i].stolen_measured ? r.devices[i].stolen_ms : 0.0;
    }
  }
  // A pre-pass (two-pass targeting) is host work here: the device reports are the
  // second pass's.
  return balance::break_down(d, r.frame_ms - r.first_pass_ms, host_ms(r));
}

bool full_quality(const FrameRecord& r) {
  return r.quality.image_scale == 1 && r.quality.step_scale == 1 && r.first_pass_ms == 0;
}

int default_warmup(int frames) { return std::clamp(frames / 4, 0, 10); }

RunSummary summarize(const std::vector<FrameRecord>& recs, int warmup,
                     const std::vector<IdealSample>& ideal, int perturb_frame) {
  RunSummary sum;
  int counted = 0;
  for (const auto& r : recs)
    if (r.frame >= warmup) {
      sum.mean_frame_ms += frame_total_ms(r), sum.mean_imbalance += r.imbalance;
      sum.mean_deviation += r.deviation, ++counted;
    }
  if (counted > 0)
    sum.mean_frame_ms /= counted, sum.mean_imbalance /= counted, sum.mean_deviation /= counted;
  // Efficiency over all frames >= warm-up: the devices' alone times of a frame between two
  // timed ones are interpolated linearly (frame cost changes smoothly along a camera path;
  // timing the devices alone on every frame would cost more than the run itself). They are
  // timed at full quality, so frames rendered at another (frame-time targeting) are left out.
  std::vector<balance::Breakdown> parts;
  sum.stolen_measured = true;
  for (const auto& r : recs) {
    if (r.frame < warmup || !full_quality(r)) continue;
    parts.push_back(frame_breakdown(r, ideal));
    if (!parts.back().valid) continue;
    sum.wall_ms += r.wall_ms + r.denoise_ms;  // the denoiser runs after the engine returns
    for (const DeviceReport& d : r.devices) sum.stolen_measured &= d.stolen_measured;
  }
  sum.breakdown = balance::mean_breakdown(parts);
  int valid = 0;
  for (const balance::Breakdown& b : parts) valid += b.valid;
  sum.wall_ms = valid > 0 ? sum.wall_ms / valid : 0.0;
  sum.stolen_measured &= valid > 0;
  sum.efficiency = sum.breakdown.efficiency();
  sum.ideal_ms = sum.breakdown.valid ? sum.breakdown.ideal : 0.0;
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

namespace {
// Deviation and imbalance differ only with three or more devices, where the fastest can
// be further below the mean than the slowest is above it.
bool deviation_differs(const std::vector<RunSummary>& summaries) {
  for (const RunSummary& s : summaries)
    if (std::abs(s.mean_deviation - s.mean_imbalance) > 5e-4) return true;
  return false;
}
}  // namespace

void print_table(const std::vector<std::string>& specs, const std::vector<RunSummary>& summaries,
                 bool perturbed) {
  size_t width = 14;  // the longest label, so specs and lane names are never cut
  for (const std::string& spec : specs) width = std::max(width, spec.size());
  const bool deviation = deviation_differs(summaries);
  print_out("\n{:<{}} {:>10} {:>10}{} {:>10} {:>9}{}\n", "balancer", width, "frame ms",
            "imbalance", deviation ? fmt::format(" {:>10}", "deviation") : "", "efficiency",
            "speedup", perturbed ? fmt::format(" {:>9}", "recovery") : "");
  for (size_t k = 0; k < specs.size(); ++k) {
    const RunSummary& s = summaries[k];
    print_out("{:<{}} {:>10.1f} {:>9.1f}%{} {:>10} {:>9}{}\n", specs[k], width, s.mean_frame_ms,
              100 * s.mean_imbalance,
              deviation ? fmt::format(" {:>9.1f}%", 100 * s.mean_deviation) : "",
              s.efficiency > 0 ? fmt::format("{:.3f}", s.efficiency) : "-",
              s.speedup > 0 ? fmt::format("{:.2f}x", s.speedup) : "-",
              !perturbed               ? ""
              : s.recovery_frames >= 0 ? fmt::format(" {:>9}", s.recovery_frames)
                                       : fmt::format(" {:>9}", "never"));
  }
  print_out(
      "(frame ms: devices + host, mean over the frames after the warm-up; imbalance: slowest "
      "device's time / mean - 1{}{})\n",
      deviation ? "; deviation (Harada): max |time - mean| / mean" : "",
      perturbed ? "; recovery: frames after --perturb until imbalance stays under 5%, "
                  "never: not by the end"
                : "");
  if (!deviation)
    print_out(
        "(Harada's deviation, max |time - mean| / mean, equals the imbalance in every row; "
        "with two devices it always does)\n");
}

void print_breakdown(const std::vector<std::string>& specs,
                     const std::vector<RunSummary>& summaries) {
  size_t width = 14;
  for (const std::string& spec : specs) width = std::max(width, spec.size());
  bool any = false, stolen_everywhere = true;
  for (const RunSummary& s : summaries)
    any |= s.breakdown.valid, stolen_everywhere &= !s.breakdown.valid || s.stolen_measured;
  if (!any) return;
  print_out(
      "\nwhere the time goes (ms per frame, mean over full-quality frames after the "
      "warm-up):\n");
  print_out("{:<{}} {:>8} {:>8} {:>8} {:>9} {:>8} {:>8} {:>10}\n", "balancer", width, "frame",
            "ideal", "balance", "overhead", "stolen", "host", "accounted");
  for (size_t k = 0; k < specs.size(); ++k) {
    const balance::Breakdown& b = summaries[k].breakdown;
    if (!b.valid) continue;
    print_out("{:<{}} {:>8.2f} {:>8.2f} {:>8.2f} {:>9.2f} {:>8.2f} {:>8.2f} {:>9.1f}%\n", specs[k],
              width, b.total, b.ideal, b.balance_loss, b.overhead, b.stolen, b.host,
              summaries[k].wall_ms > 0 ? 100 * b.total / summaries[k].wall_ms : 0.0);
  }
  print_out(
      "(frame = ideal + balance (devices idle, waiting for the last) + overhead (per item: "
      "launches, pulls, caches) + stolen (device threads runnable but not running) + host "
      "(planning, gathering, compositing); each device weighted by its share of the ideal "
      "speed; accounted: frame / the engine's measured wall time{})\n",
      stolen_everywhere ? ""
                        : "; stolen time is measured on CPU devices without a quota only, "
                          "elsewhere it is inside overhead");
  for (size_t k = 0; k < specs.size(); ++k) {
    const std::string why = balance::above_one_explanation(summaries[k].breakdown);
    if (!why.empty()) print_out("note: {}: {}\n", specs[k], why);
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
          {"rebalances", s.rebalances},
          {"breakdown", breakdown_to_json(s.breakdown, s.stolen_measured, s.wall_ms)}};
}

nlohmann::json breakdown_to_json(const balance::Breakdown& b, bool stolen_measured,
                                 double wall_ms) {
  if (!b.valid) return nullptr;
  return {{"frame_ms", b.total},
          {"ideal_ms", b.ideal},
          {"balance_loss_ms", b.balance_loss},
          {"overhead_ms", b.overhead},
          {"stolen_ms", b.stolen},
          {"stolen_measured", stolen_measured},
          {"host_ms", b.host},
          {"engine_wall_ms", wall_ms},
          {"efficiency", b.efficiency()},
          {"above_one", balance::above_one_explanation(b)}};
}

std::vector<std::string> lane_file_stems(const std::vector<std::string>& names) {
  std::vector<std::string> stems;
  std::map<std::string, int> seen;
  for (const std::string& n : names) {
    const int k = ++seen[n];
    stems.push_back(k == 1 ? n : n + "-" + std::to_string(k));
  }
  return stems;
}

}  // namespace multiray::study
