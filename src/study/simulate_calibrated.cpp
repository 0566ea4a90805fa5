#include "study/simulate_calibrated.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "balance/trace_calibration.h"
#include "core/console.h"
#include "core/error.h"
#include "core/file_io.h"
#include "run/parse_options.h"
#include "study/calibration_report.h"
#include "study/stats_json.h"

namespace multiray::study {

balance::Trace load_trace(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read trace '" + path + "'");
  try {
    return balance::read_trace(in);
  } catch (const std::invalid_argument& e) {
    throw InputError("trace '" + path + "': " + e.what());
  }
}

namespace {

// A real run must be of the same devices and frames as the calibration trace.
void check_match(const balance::Trace& cal, const balance::Trace& real, const std::string& path) {
  auto refuse = [&](const std::string& what) {
    throw InputError("--predict: trace '" + path + "' " + what);
  };
  if (real.devices.size() != cal.devices.size())
    refuse(fmt::format("has {} devices, the calibration trace {}", real.devices.size(),
                       cal.devices.size()));
  if (real.frames.size() != cal.frames.size())
    refuse(fmt::format("has {} frames, the calibration trace {}", real.frames.size(),
                       cal.frames.size()));
  for (size_t f = 0; f < cal.frames.size(); ++f) {
    const balance::FrameShape &a = cal.frames[f].shape, &b = real.frames[f].shape;
    if (!a.same_size(b))
      refuse(fmt::format("has frames of {}x{} x {} views, the calibration trace {}x{} x {}",
                         b.width, b.height, b.views, a.width, a.height, a.views));
  }
}

struct Row {
  std::string balancer;
  bool has_real = false;
  double real = 0, simulated = 0, error = 0, bias = 0;  // means over frames >= warm-up
  double plain = 0, plain_error = 0;                    // without calibration
  std::vector<double> real_ms, simulated_ms;            // per frame >= warm-up
};

// Mean of `sim`, and its mean |error| per frame against `real` (frame times, ms).
void compare(const std::vector<double>& real, const std::vector<double>& sim, double& sim_mean,
             double& error) {
  double s = 0, e = 0;
  for (size_t f = 0; f < sim.size(); ++f) {
    s += sim[f];
    if (!real.empty() && real[f] > 0) e += std::abs(sim[f] - real[f]) / real[f];
  }
  sim_mean = sim.empty() ? 0 : s / double(sim.size());
  error = sim.empty() ? 0 : e / double(sim.size());
}

std::vector<double> replayed(const balance::Trace& trace, const std::string& spec,
                             const std::vector<balance::SimDevice>* devices, int warmup,
                             uint64_t seed) {
  auto balancer = make_balancer_or_throw(spec, int(trace.devices.size()), "the trace");
  std::function<std::vector<balance::SimDevice>(int)> at;
  if (devices) at = [devices](int) { return *devices; };
  std::vector<double> out;
  const auto run = balance::replay_trace(trace, *balancer, at, {}, 0, seed);
  for (size_t f = size_t(warmup); f < run.size(); ++f) out.push_back(run[f].frame_ms);
  return out;
}

Row row(const balance::Trace& trace, const balance::Trace& net,
        const std::vector<balance::SimDevice>& devices, const std::string& spec,
        const balance::Trace* real, const CalibratedRun& o, int warmup) {
  Row r;
  r.balancer = spec;
  std::vector<double> truth;
  if (real) {
    for (size_t f = size_t(warmup); f < real->frames.size(); ++f)
      truth.push_back(balance::frame_time_ms(real->frames[f]));
    double sum = 0;
    for (double t : truth) sum += t;
    r.has_real = !truth.empty();
    r.real = r.has_real ? sum / double(truth.size()) : 0;
  }
  r.real_ms = truth;
  r.simulated_ms = replayed(net, spec, &devices, warmup, o.seed);
  compare(truth, r.simulated_ms, r.simulated, r.error);
  compare(truth, replayed(trace, spec, nullptr, warmup, o.seed), r.plain, r.plain_error);
  r.bias = r.real > 0 ? r.simulated / r.real - 1 : 0;
  return r;
}

void print_rows(const std::vector<Row>& rows, int warmup, int frames) {
  print_out(
      "frames {}-{} (largest device time per frame; real: measured, simulated: virtual "
      "time on the calibrated devices; plain: uncalibrated replay)\n",
      warmup, frames - 1);
  print_out("{:<24} {:>10} {:>10} {:>8} {:>8} {:>10} {:>9}\n", "balancer", "real ms", "sim ms",
            "|err|", "bias", "plain ms", "plain err");
  for (const Row& r : rows) {
    auto pct = [&](double v) { return r.has_real ? fmt::format("{:.2f}%", 100 * v) : "-"; };
    print_out("{:<24} {:>10} {:>10.3f} {:>8} {:>8} {:>10.3f} {:>9}\n", r.balancer.substr(0, 24),
              r.has_real ? fmt::format("{:.3f}", r.real) : "-", r.simulated, pct(r.error),
              pct(r.bias), r.plain, pct(r.plain_error));
  }
}

}  // namespace

int simulate_calibrated(const balance::Trace& trace, const CalibratedRun& o) {
  if (!o.json_path.empty()) check_output_file(o.json_path, "--json");
  const nlohmann::json doc = calibrated_study(trace, o, true);
  if (!o.json_path.empty()) write_file_atomically(o.json_path, dump_json(doc) + "\n");
  return 0;
}

namespace {

// One calibration and the cost it replays: on `on` (paths) together, or on TRACE alone.
struct Calibrated {
  std::vector<std::string> on;
  balance::TraceCalibration cal;
  balance::Trace base;
  std::vector<balance::SimDevice> devices;
};

Calibrated calibrate_on(const std::vector<std::string>& paths,
                        const std::vector<const balance::Trace*>& traces, const CalibratedRun& o,
                        int warmup, bool pooled) {
  Calibrated c;
  c.on = paths;
  if (pooled) {
    c.cal = balance::calibrate_pooled(traces, warmup, o.contention);
    c.base = balance::pooled_costs(traces, c.cal);
  } else {
    c.cal = balance::calibrate(*traces[0], warmup, o.contention);
    c.base = balance::net_trace(*traces[0], c.cal);
  }
  c.devices = balance::calibrated_devices(c.cal, o.noise);
  return c;
}

void print_of(const Calibrated& c, const balance::Trace& trace, const CalibratedRun& o) {
  std::vector<std::string> names;
  for (const auto& d : trace.devices) names.push_back(d.name);
  print_calibration(c.cal, c.on, trace.balancer, names, o.contention >= 0, o.noise);
}

nlohmann::json row_json(const Row& r) {
  nlohmann::json j{{"balancer", r.balancer},
                   {"simulated_mean_ms", r.simulated},
                   {"plain_mean_ms", r.plain},
                   {"simulated_ms", r.simulated_ms}};
  if (r.has_real) {
    j["real_mean_ms"] = r.real;
    j["mean_abs_error"] = r.error;
    j["bias"] = r.bias;
    j["plain_mean_abs_error"] = r.plain_error;
    j["real_ms"] = r.real_ms;
  }
  return j;
}

}  // namespace

nlohmann::json calibrated_study(const balance::Trace& trace, const CalibratedRun& o, bool print) {
  // Everything is checked before anything is printed: one line for bad input.
  const bool pooled = o.mode != "single", leave_out = o.mode == "leave-one-out";
  if (pooled && o.mode != "pooled" && !leave_out)
    throw InputError("--calibration must be single, pooled or leave-one-out, not '" + o.mode +
                     "'");
  if (pooled && o.predict.empty())
    throw InputError("--calibration " + o.mode + " needs the traces to pool in --predict");
  if (leave_out && !o.balancers.empty())
    throw InputError(
        "--balancers does not go with --calibration leave-one-out (its rows are the "
        "--predict traces, each predicted without itself)");
  std::vector<balance::Trace> reals;
  for (const std::string& path : o.predict) {
    reals.push_back(load_trace(path));
    if (pooled) {
      const std::string why =
          balance::trace_mismatch(trace, reals.back(), "the calibration trace");
      if (!why.empty()) throw InputError("--predict: trace '" + path + "' " + why);
    } else {
      check_match(trace, reals.back(), path);
    }
    make_balancer_or_throw(reals.back().balancer, int(trace.devices.size()), path);
  }
  for (const std::string& spec : o.balancers)
    make_balancer_or_throw(spec, int(trace.devices.size()), "--balancers");
  const int frames = int(trace.frames.size());
  const int warmup = o.warmup >= 0 ? o.warmup : frames / 10;
  if (warmup >= frames) throw InputError("--warmup leaves no frame of the trace");
  // The pool: TRACE and each --predict trace once (a path named twice counts once).
  std::vector<std::string> paths{o.trace_path};
  std::vector<const balance::Trace*> pool{&trace};
  for (size_t k = 0; k < reals.size(); ++k)
    if (std::find(paths.begin(), paths.end(), o.predict[k]) == paths.end())
      paths.push_back(o.predict[k]), pool.push_back(&reals[k]);
  if (leave_out && pool.size() < 2)
    throw InputError("--calibration leave-one-out needs a trace besides each predicted one");

  std::vector<Row> rows;
  nlohmann::json list = nlohmann::json::array();
  nlohmann::json doc{{"trace", o.trace_path},
                     {"predict", o.predict},
                     {"warmup", warmup},
                     {"frames", frames},
                     {"calibration_mode", o.mode}};
  if (leave_out) {
    for (size_t k = 0; k < reals.size(); ++k) {
      std::vector<std::string> on;
      std::vector<const balance::Trace*> others;
      for (size_t r = 0; r < pool.size(); ++r)
        if (paths[r] != o.predict[k]) on.push_back(paths[r]), others.push_back(pool[r]);
      const Calibrated c = calibrate_on(on, others, o, warmup, true);
      if (print) print_of(c, trace, o);
      rows.push_back(row(trace, c.base, c.devices, reals[k].balancer, &reals[k], o, warmup));
      nlohmann::json j = row_json(rows.back());
      j["calibrated_on"] = on;
      j["calibration"] = calibration_json(c.cal);
      list.push_back(j);
    }
  } else {
    const Calibrated c = pooled ? calibrate_on(paths, pool, o, warmup, true)
                                : calibrate_on({o.trace_path}, {&trace}, o, warmup, false);
    if (print) print_of(c, trace, o);
    for (size_t k = 0; k < reals.size(); ++k)
      rows.push_back(row(trace, c.base, c.devices, reals[k].balancer, &reals[k], o, warmup));
    const std::vector<std::string> own{trace.balancer};
    for (const std::string& spec : o.balancers.empty() && reals.empty() ? own : o.balancers)
      rows.push_back(row(trace, c.base, c.devices, spec, spec == trace.balancer ? &trace : nullptr,
                         o, warmup));
    for (const Row& r : rows) list.push_back(row_json(r));
    doc["calibrated_on"] = c.on;
    doc["calibration"] = calibration_json(c.cal);
  }
  if (print) print_rows(rows, warmup, frames);
  doc["rows"] = list;
  return doc;
}

}  // namespace multiray::study
