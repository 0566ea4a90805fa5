#include "app/bench_repeats.h"

#include <fmt/core.h>

#include "app/bench_summary.h"

namespace multiray::app {

void add_block(std::vector<RepeatLane>& lanes, const std::vector<std::string>& labels,
               const BenchResult& r, int warmup) {
  if (lanes.empty())
    for (const std::string& l : labels) lanes.push_back(RepeatLane{l, {}, {}});
  std::vector<double> ideal;
  for (const IdealSample& i : r.ideal) ideal.push_back(i.ideal_ms);
  for (size_t k = 0; k < lanes.size() && k < r.lanes.size(); ++k) {
    std::vector<double> ms, eff;
    const auto& recs = r.lanes[k].records;
    for (size_t f = size_t(std::max(warmup, 0)); f < recs.size(); ++f) {
      ms.push_back(recs[f].frame_ms);
      eff.push_back(ideal.empty() || !(recs[f].frame_ms > 0)
                        ? NAN
                        : interpolate_ideal(r.sampled, ideal, int(f)) / recs[f].frame_ms);
    }
    lanes[k].frame_ms.push_back(std::move(ms));
    lanes[k].efficiency.push_back(std::move(eff));
  }
}

RepeatSummary summarize_repeats(const std::vector<RepeatLane>& lanes) {
  RepeatSummary s;
  std::vector<balance::Blocks> times;
  for (const RepeatLane& l : lanes) {
    s.labels.push_back(l.label);
    s.efficiency.push_back(balance::bootstrap_median(l.efficiency));
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
}  // namespace

void print_repeats(const RepeatSummary& s) {
  size_t width = 8;
  for (const std::string& l : s.labels) width = std::max(width, l.size());
  fmt::print(
      "\n{} repeat blocks: medians over frames with 95% intervals (bootstrap over "
      "blocks and frames)\n",
      s.blocks);
  fmt::print("{:<{}}  {:>26}  {:>22}  {:>22}\n", "balancer", width, "frame ms", "efficiency",
             "x best (per frame)");
  for (size_t k = 0; k < s.labels.size(); ++k)
    fmt::print("{:<{}}  {:>26}  {:>22}  {:>22}\n", s.labels[k], width,
               interval(s.time.medians[k], "{:.2f}"), interval(s.efficiency[k], "{:.3f}"),
               int(k) == s.time.best ? std::string("best") : interval(s.time.ratios[k], "{:.3f}"));
  fmt::print("verdict: {}\n", s.time.text);
  for (size_t k = 0; k < s.labels.size(); ++k)
    if (s.efficiency[k].valid && s.efficiency[k].median > 1.0)
      fmt::print(
          "note: {}'s efficiency is above 1: the ideal comes from each device timed alone on "
          "sampled frames, so it is only as good as that measurement; a device that ran "
          "faster in the run than when it was timed (less load, a warmer cache) makes the "
          "ideal too slow\n",
          s.labels[k]);
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
                     {"ratio_to_best", j(s.time.ratios[k])}});
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

}  // namespace multiray::app
