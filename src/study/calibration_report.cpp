#include "study/calibration_report.h"

#include <fmt/core.h>

#include "core/console.h"

namespace multiray::study {

namespace {

std::string ms_or(bool fitted, double v, const char* otherwise) {
  return fitted ? fmt::format("{:.4f}", v) : std::string(otherwise);
}

void print_contention(const balance::TraceCalibration& cal, bool given, double noise) {
  print_out(
      "contention {:.4f} ({}; {:.1f}% of the cost rendered alone), frame noise {:.4f} "
      "(learnt; simulated with {:g})\n",
      cal.contention,
      given                       ? "given by --contention"
      : cal.contention_identified ? "learnt"
      : cal.pooled                ? "not identifiable from these traces: 0, see --contention"
                                  : "not identifiable from this trace: 0, see --contention",
      100 * cal.alone_share, cal.frame_noise, noise);
}

}  // namespace

void print_calibration(const balance::TraceCalibration& cal, const std::vector<std::string>& on,
                       const std::string& balancer, const std::vector<std::string>& names,
                       bool contention_given, double noise) {
  if (!cal.pooled) {
    print_out("calibration on {} ({} frames after warm-up, recorded with {}):\n",
              on.empty() ? "" : on[0], cal.frames, balancer);
    print_out("{:>6} {:>8} {:>14} {:>15} {:>10} {:>6}  {}\n", "device", "speed", "item cost ms",
              "frame cost ms", "launch ms", "items", "name");
    for (size_t d = 0; d < cal.devices.size(); ++d) {
      const balance::CalibratedDevice& c = cal.devices[d];
      print_out("{:>6} {:>8.4f} {:>14} {:>15.4f} {:>10} {:>6}  {}\n", d, c.speed,
                ms_or(c.overhead_fitted, c.item_overhead_ms, "- (no fit)"), c.frame_overhead_ms,
                c.launch_ms > 0 ? fmt::format("{:.3f}", c.launch_ms) : std::string("-"), c.items,
                d < names.size() ? names[d] : "");
    }
    print_contention(cal, contention_given, noise);
    return;
  }
  std::string list;
  for (const std::string& p : on) list += (list.empty() ? "" : ", ") + p;
  print_out(
      "calibration pooled on {} traces ({}; {} frames each after warm-up; plans made again "
      "in {} of {} frames):\n",
      cal.traces, list, cal.frames, cal.plans_matched, cal.plans);
  print_out("{:>6} {:>8} {:>14} {:>9} {:>15} {:>14} {:>6} {:>6}  {}\n", "device", "speed",
            "take cost ms", "takes as", "frame cost ms", "in 1st take", "items", "takes", "name");
  for (size_t d = 0; d < cal.devices.size(); ++d) {
    const balance::CalibratedDevice& c = cal.devices[d];
    print_out("{:>6} {:>8.4f} {:>14} {:>9} {:>15.4f} {:>14} {:>6} {:>6}  {}\n", d, c.speed,
              ms_or(c.overhead_fitted, c.item_overhead_ms + c.launch_ms, "- (no fit)"),
              c.batching ? "launches" : "items", c.frame_overhead_ms,
              ms_or(c.first_take_fitted, c.first_take_ms, "-"), c.items, c.takes,
              d < names.size() ? names[d] : "");
  }
  print_contention(cal, contention_given, noise);
}

nlohmann::json calibration_json(const balance::TraceCalibration& cal) {
  nlohmann::json devices = nlohmann::json::array();
  for (const auto& d : cal.devices) {
    nlohmann::json j{{"speed", d.speed},
                     {"item_overhead_ms", d.item_overhead_ms},
                     {"item_overhead_fitted", d.overhead_fitted},
                     {"frame_overhead_ms", d.frame_overhead_ms},
                     {"launch_ms", d.launch_ms},
                     {"items", d.items}};
    if (cal.pooled) {
      j["batching"] = d.batching;
      j["first_take_ms"] = d.first_take_ms;
      j["first_take_fitted"] = d.first_take_fitted;
      j["takes"] = d.takes;
    }
    devices.push_back(j);
  }
  nlohmann::json out{{"devices", devices},
                     {"contention", cal.contention},
                     {"contention_identified", cal.contention_identified},
                     {"alone_share", cal.alone_share},
                     {"frame_noise", cal.frame_noise},
                     {"frames", cal.frames}};
  if (cal.pooled) {
    out["traces"] = cal.traces;
    out["plans_matched"] = cal.plans_matched;
    out["plans"] = cal.plans;
  }
  return out;
}

}  // namespace multiray::study
