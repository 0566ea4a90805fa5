// `multiray simulate TRACE --calibrate [--predict REAL,...]`: the simulator calibrated on
// a trace (balance/trace_calibration.h) predicts other balancers on the devices that
// recorded it, against real runs of them when given.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/trace.h"

namespace multiray::study {

struct CalibratedRun {
  std::string trace_path;
  std::vector<std::string> predict;  // traces of real runs to predict (may be empty)
  // What to calibrate on: "single" (the trace alone), "pooled" (the trace and every
  // predict trace together) or "leave-one-out" (for each predict trace, the others and
  // the trace, without it). --calibration.
  std::string mode = "single";
  std::vector<std::string> balancers;  // without --predict: what to simulate
  int warmup = -1;                     // -1: a tenth of the frames
  double contention = -1;              // < 0: learnt from the trace
  double noise = 0;                    // per-frame speed noise of the calibrated devices
  uint64_t seed = 0;
  std::string json_path;
};

// The trace at `path`; InputError (one line naming the file) if it cannot be read or parsed.
balance::Trace load_trace(const std::string& path);

// Prints the calibration and the table (and writes --json); InputError (exit 2, one
// line) for a real trace whose devices or frames do not match the calibration trace's
// (pooled: whose devices' names or emulated speeds differ too).
int simulate_calibrated(const balance::Trace& trace, const CalibratedRun& run);

// The same work, its --json document returned (and printed as the CLI prints it when
// `print`): what multiray.simulate(..., calibrate=True) returns. run.json_path is ignored.
nlohmann::json calibrated_study(const balance::Trace& trace, const CalibratedRun& run, bool print);

}  // namespace multiray::study
