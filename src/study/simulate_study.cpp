#include "study/simulate_study.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "balance/balancer.h"
#include "core/error.h"
#include "run/run.h"
#include "util/parse.h"
#include "util/result_encoding.h"
#include "util/spec.h"

namespace multiray::study {

namespace {

// Refuses a simulation estimated to need more memory than --max-memory allows, before
// it runs: every study's frame times are kept for the summary (and the JSON), and the
// largest study holds its cost tables and one frame of `most` devices at a time.
void check_memory(const SimulateOptions& o, const balance::Trace& trace, int most, double runs,
                  int frames, bool keeps_json) {
  const double limit = parse_memory_limit(o.max_memory);
  const double times = runs * frames * 8.0;
  const double study = balance::study_memory_bytes(trace, most, frames);
  // nlohmann::json holds each time as a 16-byte value, then the text is built: measured,
  // 2 x 10^6 frame times took 111 MB with --json, 48 bytes each beyond the 8 kept.
  const double json = keeps_json ? runs * frames * 48.0 : 0;
  const double need = times + study + json;
  if (need > limit)
    throw InputError(memory_refusal(
        need,
        fmt::format("{:.1f} GB of frame times of {:g} simulations x {} frames, {:.1f} GB for the "
                    "largest simulation, {:.1f} GB of JSON",
                    times / 1e9, runs, frames, study / 1e9, json / 1e9),
        limit));
}

std::vector<int> device_counts(const std::string& text) {
  std::vector<int> out;
  for (const std::string& item : split_spec_list(text)) {
    const double n = parse_number(item).value_or(0);
    if (n != std::floor(n) || n < 1 || n > 4096)
      throw InputError("--devices: '" + item + "' is not a device count in 1..4096");
    out.push_back(int(n));
  }
  if (out.empty()) throw InputError("--devices is empty");
  return out;
}

}  // namespace

SimulationPlan plan_simulation(const SimulateOptions& o, const balance::Trace& trace,
                               bool keeps_json) {
  SimulationPlan p;
  p.counts = device_counts(o.devices);
  p.specs = o.balancers.empty() ? balance::balancer_names() : split_spec_list(o.balancers);
  if (o.balancers.empty())  // auto would simulate one of the others a second time
    std::erase(p.specs, std::string("auto"));
  if (!(o.noise >= 0 && o.noise < 1)) throw InputError("--noise must be in [0, 1)");
  balance::StudyConfig& config = p.config;
  config.frame_noise = o.noise;
  if (!(o.slowdown >= 1e-3 && o.slowdown <= 1e6))
    throw InputError("--slowdown must be in [0.001, 1e6]");
  config.slowdown = o.slowdown;
  config.seed = o.seed;
  config.frames = o.frames;
  if (o.frames < 0 || o.frames > 1000000) throw InputError("--frames must be in 0..1000000");
  p.frames = o.frames > 0 ? o.frames : int(trace.frames.size());
  config.warmup = o.warmup >= 0 ? o.warmup : p.frames / 10;
  try {
    config.link = balance::simulated_link(o.link);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--link: ") + e.what());
  }
  try {
    config.link.bytes_per_pixel = balance::simulated_bytes_per_pixel(o.results, o.zstd_ratio);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--result-encoding: ") + e.what());
  }
  // Everything is checked before anything runs: one line for bad input.
  for (int n : p.counts) {
    try {
      p.speeds.push_back(balance::device_speeds(o.speeds, n, o.seed));
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("--speeds: ") + e.what());
    }
    for (const std::string& spec : p.specs) make_balancer_or_throw(spec, n, "--balancers");
  }
  check_memory(o, trace, *std::max_element(p.counts.begin(), p.counts.end()),
               double(p.counts.size() * p.specs.size()), p.frames, keeps_json);
  return p;
}

std::vector<balance::StudyResult> run_simulation(
    const balance::Trace& trace, SimulationPlan& plan,
    const std::function<void(const std::string& spec, const balance::StudyResult&)>& on_result) {
  balance::StudyConfig& config = plan.config;
  std::vector<balance::StudyResult> results;
  balance::TraceCosts costs(trace);  // each traced frame's cost table built once
  for (size_t c = 0; c < plan.counts.size(); ++c) {
    config.speeds = plan.speeds[c];
    for (const std::string& spec : plan.specs) {
      try {
        results.push_back(balance::run_study(trace, spec, config, &costs));
      } catch (const std::invalid_argument& e) {
        throw InputError(std::string("--balancers: ") + e.what());
      }
      if (on_result) on_result(spec, results.back());
    }
  }
  return results;
}

nlohmann::json simulation_to_json(const SimulateOptions& o, const SimulationPlan& plan,
                                  const std::vector<balance::StudyResult>& results) {
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& r : results)
    runs.push_back({{"balancer", r.balancer},
                    {"devices", r.devices},
                    {"mean_frame_ms", r.mean_frame_ms},
                    {"mean_ideal_ms", r.mean_ideal_ms},
                    {"efficiency", r.efficiency},
                    {"mean_imbalance", r.mean_imbalance},
                    {"mean_deviation", r.mean_deviation},
                    {"frame_ms", r.frame_ms}});
  return {{"trace", o.trace_path},
          {"speeds", o.speeds},
          {"noise", o.noise},
          {"slowdown", o.slowdown},
          {"link", o.link},
          {"result_encoding", o.results},
          {"result_bytes_per_pixel", plan.config.link.bytes_per_pixel},
          {"frames", plan.frames},
          {"warmup", plan.config.warmup},
          {"timing",
           "virtual time (simulated); ideal = frame cost / sum of "
           "device speeds, without link or noise"},
          {"runs", runs}};
}

CalibratedRun calibrated_run(const SimulateOptions& o) {
  CalibratedRun run;
  run.trace_path = o.trace_path;
  run.predict = split_spec_list(o.predict);
  run.mode = o.calibration;
  run.balancers = split_spec_list(o.balancers);
  run.warmup = o.warmup;
  if (o.contention != -1 && !(o.contention >= 0 && o.contention <= 10))
    throw InputError("--contention must be in [0, 10]");
  run.contention = o.contention;
  if (!(o.noise >= 0 && o.noise < 1)) throw InputError("--noise must be in [0, 1)");
  run.noise = o.noise;
  run.seed = o.seed;
  run.json_path = o.json_path;
  return run;
}

}  // namespace multiray::study
