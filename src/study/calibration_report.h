// The calibration as `multiray simulate --calibrate` prints it and as its --json holds
// it (balance/trace_calibration.h), one trace's or several traces' pooled.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/trace_calibration.h"

namespace multiray::study {

// The table of learnt devices under a heading naming what it was calibrated on
// (`on`: the trace paths; `names`: the device names); `contention_given`: --contention.
void print_calibration(const balance::TraceCalibration& cal, const std::vector<std::string>& on,
                       const std::string& balancer, const std::vector<std::string>& names,
                       bool contention_given, double noise);

nlohmann::json calibration_json(const balance::TraceCalibration& cal);

}  // namespace multiray::study
