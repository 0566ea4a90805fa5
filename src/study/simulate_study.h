// The work of `multiray simulate TRACE` without its printing: the options checked as the
// CLI checks them, the studies run (balance/sim_study.h) and the --json document built.
// The CLI (app/simulate_command.cpp) prints its table around these; the Python module's
// simulate() (src/python/studies.cpp) returns the document as Python data.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/sim_study.h"
#include "balance/trace.h"
#include "study/simulate_calibrated.h"

namespace multiray::study {

// The options of `multiray simulate`, named as the CLI's.
struct SimulateOptions {
  std::string trace_path;
  std::string devices = "2,4,8,16";
  std::string speeds = "equal";
  double noise = 0;
  double slowdown = 1;
  std::string link = "none";
  std::string results = "rgba8";  // result bytes per pixel (balance::simulated_bytes_per_pixel)
  double zstd_ratio = -1;         // negative: the measured one
  std::string balancers;          // empty: all
  int frames = 0;
  int warmup = -1;  // -1: a tenth of the frames
  uint64_t seed = 0;
  std::string json_path, plot_path;
  bool validate = false;
  bool calibrate = false;
  std::string predict;                 // real traces, comma-separated (implies --calibrate)
  double contention = -1;              // < 0: learnt by --calibrate
  std::string calibration = "single";  // single, pooled or leave-one-out (CalibratedRun::mode)
  std::string max_memory = "auto";     // as render's --max-memory
};

// What a plain simulation runs: every device count with every balancer spec, the studies'
// shared configuration (config.speeds is set per count from `speeds`).
struct SimulationPlan {
  std::vector<int> counts;
  std::vector<std::string> specs;
  std::vector<std::vector<double>> speeds;  // per count
  balance::StudyConfig config;
  int frames = 0;  // simulated frames (the trace's when --frames is 0)
};

// Checks every option against `trace` (InputError with the CLI's one-line message) and
// refuses a simulation estimated above --max-memory; `keeps_json`: the document will be
// built (--json, or the Python module), which the estimate counts.
SimulationPlan plan_simulation(const SimulateOptions& o, const balance::Trace& trace,
                               bool keeps_json);

// Runs the plan's studies, device count by device count and spec by spec; `on_result`
// (if given) sees each spec and its result as it is made (the CLI prints its row; Python checks
// for Ctrl-C and may throw to stop).
std::vector<balance::StudyResult> run_simulation(
    const balance::Trace& trace, SimulationPlan& plan,
    const std::function<void(const std::string& spec, const balance::StudyResult&)>& on_result =
        {});

// The --json document: the settings and one entry per study under "runs".
nlohmann::json simulation_to_json(const SimulateOptions& o, const SimulationPlan& plan,
                                  const std::vector<balance::StudyResult>& results);

// --calibrate / --predict: the calibrated run the options ask for. InputError for a
// contention or noise out of range.
CalibratedRun calibrated_run(const SimulateOptions& o);

}  // namespace multiray::study
