#include "study/bench_repeats.h"
#include "core/console.h"

#include <cmath>

#include <fmt/core.h>

#include "balance/stats.h"
#include "study/bench_summary.h"

namespace multiray::study {

void add_block(std::vector<RepeatLane>& lanes, const std::vector<std::string>& labels,
               const BenchResult& r, int warmup, int perturb_frame) {
  if (lanes.empty())
    for (const std::string& l : labels) lanes.push_back(RepeatLane{l, {}, {}, {}, {}, {}});
  for (size_t k = 0; k < lanes.size() && k < r.lanes.size(); ++k) {
    std::vector<double> ms, eff, imbalance, deviation, lambda;
    const auto& recs = r.lanes[k].records;
    for (const FrameRecord& rec : recs) lambda.push_back(rec.imbalance);
    for (size_t f = size_t(std::max(warmup, 0)); f < recs.size(); ++f) {
      ms.push_back(frame_total_ms(recs[f]));
      imbalance.push_back(recs[f].imbalance);
      deviation.push_back(recs[f].deviation);
      if (full_quality(recs[f])) eff.push_back(frame_breakdown(recs[f], r.ideal).efficiency());
    }
    RepeatLane& lane = lanes[k];
    lane.frame_ms.push_back(std::move(ms));
    lane.efficiency.push_back(std::move(eff));
    lane.imbalance.push_back(std::move(imbalance));
    lane.deviation.push_back(std::move(deviation));
    const int recovered = perturb_frame >= 0 ? balance::recovered_from(lambda, perturb_frame) : -1;
    lane.recovery.push_back(
        {perturb_frame >= 0 && recovered >= 0 ? double(recovered - perturb_frame) : NAN});
  }
}

RepeatSummary summarize_repeats(const std::vector<RepeatLane>& lanes, bool perturbed) {
  RepeatSummary s;
  s.perturbed = perturbed;
  std::vector<balance::Blocks> times;
  for (const RepeatLane& l : lanes) {
    s.labels.push_back(l.label);
    s.efficiency.push_back(balance::bootstrap_median(l.efficiency));
    s.imbalance.push_back(balance::bootstrap_median(l.imbalance));
    s.deviation.push_back(balance::bootstrap_median(l.deviation));
    s.recovery.push_back(balance::bootstrap_median(l.recovery));
    int recovered = 0;
    for (const std::vector<double>& block : l.recovery)
      recovered += !block.empty() && std::isfinite(block.front());
    s.recovered_blocks.push_back(recovered);
    std::vector<double> medians;
    for (const std::vector<double>& block : l.frame_ms)
      medians.push_back(balance::bootstrap_median({block}, {.resamples = 0}).median);
    s.block_medians.push_back(std::move(medians));
    times.push_back(l.frame_ms);
    s.blocks = std::max(s.blocks, int(l.frame_ms.size()));
  }
  s.time = balance::verdict(s.labels, times);
  return s;
}

namespace {
std::string interval(const balance::Interval& i, const char* format) {
  if (!i.valid) return "-";
  return fmt::format(fmt::runtime(std::string(format) + " [" + format + ", " + format + "]"),
                     i.median, i.lo, i.hi);
}

// "never", "5 [5, 5]", or "31 [31, 31] (2/3)" when only some blocks recovered.
std::string recovery_text(const RepeatSummary& s, size_t k) {
  if (!s.recovery[k].valid) return "never";
  std::string text = interval(s.recovery[k], "{:.0f}");
  if (s.recovered_blocks[k] < s.blocks)
    text += fmt::format(" ({}/{})", s.recovered_blocks[k], s.blocks);
  return text;
}
}  // namespace

void print_repeats(const RepeatSummary& s) {
  size_t width = 8;
  for (const std::string& l : s.labels) width = std::max(width, l.size());
  const bool recovery = s.perturbed;
  bool deviation = false;
  for (size_t k = 0; k < s.labels.size(); ++k) {
    deviation |= s.deviation[k].valid && s.imbalance[k].valid &&
                 std::abs(s.deviation[k].median - s.imbalance[k].median) > 5e-4;
  }
  print_out(
      "\n{} repeat blocks: medians over frames with 95% intervals (bootstrap over "
      "blocks and frames)\n",
      s.blocks);
  print_out("{:<{}}  {:>24}  {:>22}  {:>22}{}{}  {:>22}\n", "balancer", width, "frame ms",
            "efficiency", "imbalance %", deviation ? fmt::format("  {:>22}", "deviation %") : "",
            recovery ? fmt::format("  {:>22}", "recovery") : "", "x best (per frame)");
  auto percent = [](balance::Interval i) {
    i.median *= 100, i.lo *= 100, i.hi *= 100;
    return interval(i, "{:.1f}");
  };
  for (size_t k = 0; k < s.labels.size(); ++k)
    print_out("{:<{}}  {:>24}  {:>22}  {:>22}{}{}  {:>22}\n", s.labels[k], width,
              interval(s.time.medians[k], "{:.2f}"), interval(s.efficiency[k], "{:.3f}"),
              percent(s.imbalance[k]),
              deviation ? fmt::format("  {:>22}", percent(s.deviation[k])) : "",
              recovery ? fmt::format("  {:>22}", recovery_text(s, k)) : "",
              int(k) == s.time.best ? std::string("best") : interval(s.time.ratios[k], "{:.3f}"));
  print_out("verdict: {}\n", s.time.text);
  for (size_t k = 0; k < s.labels.size(); ++k)
    if (s.efficiency[k].valid && s.efficiency[k].median > 1.0)
      print_out(
          "note: {}'s median efficiency is above 1: in most frames the devices worked faster "
          "than when each was timed alone (a negative overhead in the breakdown), so the ideal "
          "is too slow by at least that much\n",
          s.labels[k]);
}

nlohmann::json regret_of(const std::vector<RepeatLane>& lanes, const RepeatSummary& s) {
  const balance::Verdict& v = s.time;
  const size_t n = s.labels.size();
  size_t deflt = n, best = n;
  for (size_t k = 0; k < n && k < v.medians.size() && k < lanes.size(); ++k) {
    if (s.labels[k] == "auto") deflt = k;
    if (s.labels[k].rfind("subset:", 0) == 0 && v.medians[k].valid &&
        (best == n || v.medians[k].median < v.medians[best].median))
      best = k;
  }
  if (deflt == n || best == n) return {{"text", "regret: not measured"}};
  // The two lanes alone: the interval of their per-frame ratio.
  const balance::Verdict pair = balance::verdict({s.labels[deflt], s.labels[best]},
                                                 {lanes[deflt].frame_ms, lanes[best].frame_ms});
  balance::Interval r;
  if (pair.best == 1) {
    r = pair.ratios[0];
  } else if (pair.best == 0 && pair.ratios[1].valid && pair.ratios[1].lo > 0) {
    const balance::Interval& q = pair.ratios[1];  // the subset's ratio to the default
    r = {1 / q.median, 1 / q.hi, 1 / q.lo, true};
  }
  if (!r.valid) return {{"text", "regret: no interval (it needs --repeats 2 or more)"}};
  const std::string verdict = r.lo > 1   ? "slower than the best subset"
                              : r.hi < 1 ? "faster than every subset"
                                         : "tied with the best subset";
  return {{"ratio", {{"median", r.median}, {"lo", r.lo}, {"hi", r.hi}}},
          {"best_subset", s.labels[best]},
          {"text", fmt::format("regret: {} {:.1f} ms, best subset {} {:.1f} ms: {:.3f}x "
                               "[{:.3f}, {:.3f}] per frame ({})",
                               s.labels[deflt], v.medians[deflt].median, s.labels[best],
                               v.medians[best].median, r.median, r.lo, r.hi, verdict)}};
}

nlohmann::json repeats_to_json(const RepeatSummary& s) {
  auto j = [](const balance::Interval& i) {
    return i.valid ? nlohmann::json{{"median", i.median}, {"lo", i.lo}, {"hi", i.hi}}
                   : nlohmann::json();
  };
  nlohmann::json lanes = nlohmann::json::array();
  for (size_t k = 0; k < s.labels.size(); ++k)
    lanes.push_back({{"lane", s.labels[k]},
                     {"frame_ms", j(s.time.medians[k])},
                     {"efficiency", j(s.efficiency[k])},
                     {"imbalance", j(s.imbalance[k])},
                     {"deviation", j(s.deviation[k])},
                     {"recovery_frames", j(s.recovery[k])},
                     {"recovered_blocks", s.recovered_blocks[k]},
                     {"ratio_to_best", j(s.time.ratios[k])},
                     {"block_median_frame_ms", s.block_medians[k]}});
  nlohmann::json tied = nlohmann::json::array();
  for (int t : s.time.tied) tied.push_back(s.labels[size_t(t)]);
  return {{"blocks", s.blocks},
          {"confidence", 0.95},
          {"method",
           "median over frames after the warm-up; 95% interval from a two-level bootstrap "
           "(blocks, then frames within blocks; 2000 resamples); ratios per frame to the "
           "lane with the lowest median frame time"},
          {"lanes", lanes},
          {"best",
           s.time.best >= 0 ? nlohmann::json(s.labels[size_t(s.time.best)]) : nlohmann::json()},
          {"tied_with_best", tied},
          {"verdict", s.time.text}};
}

std::vector<ComparisonBar> comparison_bars(const RepeatSummary& repeats,
                                           const std::vector<RunSummary>& block0) {
  // Efficiency 0 means "not measured"; an imbalance of 0 is a value.
  auto point = [](double v, bool zero_is_value) {
    return balance::Interval{v, v, v, std::isfinite(v) && (v > 0 || (zero_is_value && v == 0))};
  };
  std::vector<ComparisonBar> bars;
  for (size_t k = 0; k < block0.size(); ++k) {
    if (repeats.blocks > 1 && k < repeats.labels.size())
      bars.push_back(ComparisonBar{repeats.labels[k], repeats.efficiency[k], repeats.imbalance[k],
                                   repeats.time.medians[k]});
    else
      bars.push_back(ComparisonBar{
          k < repeats.labels.size() ? repeats.labels[k] : "", point(block0[k].efficiency, false),
          point(block0[k].mean_imbalance, true), point(block0[k].mean_frame_ms, false)});
  }
  return bars;
}

balance::NoiseVerdict judge_noise(balance::NoiseReadings& readings,
                                  const std::vector<RepeatLane>& lanes) {
  readings.lane_frame_ms.clear();
  readings.lane_names.clear();
  for (const RepeatLane& l : lanes) {
    readings.lane_frame_ms.push_back(l.frame_ms);
    readings.lane_names.push_back(l.label);
  }
  return balance::noise_gate(readings);
}

namespace {
std::string probe_text(double p) { return std::isnan(p) ? "not run" : fmt::format("{:.2f}", p); }
}  // namespace

void print_noise(const balance::NoiseReadings& readings, const balance::NoiseVerdict& verdict) {
  if (!verdict.trustworthy) {
    print_err("multiray: warning: these figures are not trustworthy: {}\n", verdict.reason);
    return;
  }
  print_out(
      "machine: contention probe {} before, {} after (1 = no other load); hypervisor steal "
      "{:.1f}%; block spread {:.0f}%: quiet enough to trust\n",
      probe_text(readings.probe_before), probe_text(readings.probe_after), 100 * readings.steal,
      100 * verdict.spread);
}

nlohmann::json noise_to_json(const balance::NoiseReadings& readings,
                             const balance::NoiseVerdict& verdict) {
  auto number = [](double x) { return std::isnan(x) ? nlohmann::json() : nlohmann::json(x); };
  const balance::NoiseLimits limits;
  return {{"contention_probe_before", number(readings.probe_before)},
          {"contention_probe_after", number(readings.probe_after)},
          {"steal_fraction", readings.steal},
          {"block_spread", verdict.spread},
          {"limits",
           {{"min_probe", limits.min_probe},
            {"max_probe", limits.max_probe},
            {"max_steal", limits.max_steal},
            {"max_spread", limits.max_spread}}},
          {"trustworthy", verdict.trustworthy},
          {"reason", verdict.reason}};
}

}  // namespace multiray::study
