// `multiray simulate`: a recorded trace replayed on many virtual devices, behind an
// emulated link, with every balancer, in virtual time (balance/sim_study.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "balance/balancer.h"
#include "balance/sim_study.h"
#include "core/console.h"
#include "core/error.h"
#include "core/file_io.h"
#include "run/run.h"
#include "study/report_plots.h"
#include "study/simulate_calibrated.h"
#include "study/simulate_study.h"
#include "study/stats_json.h"
#include "util/parse.h"
#include "util/result_encoding.h"
#include "util/spec.h"

namespace multiray::app {

namespace {

// --validate: the trace replayed with the balancer and devices that recorded it; the
// simulated frame times against the recorded ones (the slowest device's time per frame).
int validate(const balance::Trace& trace) {
  auto balancer = make_balancer_or_throw(trace.balancer, int(trace.devices.size()), "the trace");
  const auto run = balance::replay_trace(trace, *balancer);
  print_out("replay of {} frames with {} on the {} recorded devices (speeds", trace.frames.size(),
            trace.balancer, trace.devices.size());
  for (const auto& d : trace.devices) print_out(" {:g}", d.speed);
  print_out(")\n{:>6} {:>12} {:>12} {:>8}\n", "frame", "recorded ms", "simulated ms", "error");
  double sum_err = 0, max_err = 0;
  for (size_t f = 0; f < run.size(); ++f) {
    const double rec = balance::frame_time_ms(trace.frames[f]);
    const double sim = run[f].frame_ms;
    const double err = rec > 0 ? (sim - rec) / rec : 0;
    sum_err += std::abs(err);
    max_err = std::max(max_err, std::abs(err));
    print_out("{:>6} {:>12.3f} {:>12.3f} {:>7.1f}%\n", trace.frames[f].frame, rec, sim, 100 * err);
  }
  print_out(
      "mean |error| {:.1f}%, largest {:.1f}% (device times: measured inside the devices; "
      "simulated: virtual time)\n",
      100 * sum_err / double(run.size()), 100 * max_err);
  return 0;
}

int calibrated(const study::SimulateOptions& o, const balance::Trace& trace) {
  return study::simulate_calibrated(trace, study::calibrated_run(o));
}

}  // namespace

Runner add_simulate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Replay a recorded trace (render/bench --trace) on many virtual devices, behind an "
      "emulated link, with every balancer, in virtual time");
  auto o = std::make_shared<study::SimulateOptions>();
  cmd->add_option("trace", o->trace_path, "Trace file written by render --trace")->required();
  cmd->add_option("--devices", o->devices,
                  "Device counts to simulate, comma-separated (each 1..4096)")
      ->capture_default_str();
  cmd->add_option("--speeds", o->speeds,
                  "Device speeds: equal, linear:MIN (1 down to MIN), random:MIN (uniform in "
                  "[MIN, 1], from --seed) or list:A/B/... (repeated)")
      ->capture_default_str();
  cmd->add_option("--noise", o->noise,
                  "Per-frame speed noise: each device's speed times 1 + U(-x, x) every frame")
      ->capture_default_str();
  cmd->add_option("--slowdown", o->slowdown,
                  "Every virtual device this many times slower than the recording device (e.g. "
                  "phones or small GPUs); makes rendering weigh more against the link")
      ->capture_default_str();
  cmd->add_option(
         "--link", o->link,
         "Emulated link to the master: none, lan (0.1 ms, 10 Gbit/s), wifi (5 ms, "
         "200 Mbit/s: our assumption of a shared Wi-Fi link) or LATENCY_MS,MBIT[,separate] (as "
         "render --link); the master's link is shared by all devices unless 'separate'")
      ->capture_default_str();
  cmd->add_option(
         "--result-encoding", o->results,
         "What each result pixel costs on the link: rgba8 (4 bytes of "
         "8-bit colour), or as render --result-encoding: float (12), half (6), float+zstd or "
         "half+zstd (raw bytes times --zstd-ratio)")
      ->capture_default_str();
  cmd->add_option("--zstd-ratio", o->zstd_ratio,
                  "Compressed / raw size of the zstd encodings, in (0, 1]; default: measured on "
                  "one Sponza frame (float+zstd " +
                      fmt::format("{:.3f}", measured_zstd_ratio(ResultEncoding::float_zstd)) +
                      ", half+zstd " +
                      fmt::format("{:.3f}", measured_zstd_ratio(ResultEncoding::half_zstd)) +
                      ", docs/distributed.md)");
  cmd->add_option("--balancers", o->balancers, "Balancer specs, comma-separated (default: all)");
  cmd->add_option("--frames", o->frames, "Frames to simulate (0: the trace's; more cycle it)")
      ->capture_default_str();
  cmd->add_option("--warmup", o->warmup, "Frames left out of the summary (default: a tenth)");
  cmd->add_option("--seed", o->seed, "Seed of random speeds and noise")->capture_default_str();
  cmd->add_option("--json", o->json_path, "Write every result as JSON to this file");
  cmd->add_flag("--validate", o->validate,
                "Replay the trace with the balancer and devices that recorded it and compare "
                "the simulated frame times with the recorded ones");
  cmd->add_flag("--calibrate", o->calibrate,
                "Learn the recording devices from the trace (relative speeds, fixed cost per "
                "item and per frame, contention; docs/traces.md) and replay it on them with "
                "--balancers (default: the trace's own) at the trace's frame size");
  cmd->add_option("--predict", o->predict,
                  "Traces of real runs of other balancers on the same devices, scene and "
                  "frames, comma-separated: calibrate on TRACE and compare each run's frame "
                  "times with its balancer replayed on the calibrated devices (implies "
                  "--calibrate)");
  cmd->add_option(
         "--calibration", o->calibration,
         "With --predict: what to calibrate on. single: TRACE alone; pooled: TRACE and every "
         "--predict trace together (the lanes of one bench run: each device's speed and "
         "fixed costs fitted on all their items, each frame's cost from all of them); "
         "leave-one-out: each --predict trace predicted by a calibration on TRACE and the "
         "other --predict traces, without it (docs/traces.md)")
      ->capture_default_str();
  cmd->add_option("--contention", o->contention,
                  "With --calibrate: each device's slowdown per other device at work, in "
                  "[0, 10], instead of the one learnt (when the trace cannot show it)");
  cmd->add_option("--plot", o->plot_path, "Write efficiency vs device count as SVG");
  cmd->add_option("--max-memory", o->max_memory,
                  "Refuse simulations estimated to need more memory than this: auto (half of "
                  "physical memory) or a size such as 8G or 512M")
      ->capture_default_str();
  return [o]() -> int {
    if (!o->json_path.empty()) check_output_file(o->json_path, "--json");
    if (!o->plot_path.empty()) check_output_file(o->plot_path, "--plot");
    const balance::Trace trace = study::load_trace(o->trace_path);
    if (o->validate) return validate(trace);
    if (o->calibrate || !o->predict.empty() || o->calibration != "single")
      return calibrated(*o, trace);
    study::SimulationPlan plan = study::plan_simulation(*o, trace, !o->json_path.empty());
    const std::vector<int>& counts = plan.counts;
    const std::vector<std::string>& specs = plan.specs;
    const int frames = plan.frames;
    const balance::StudyConfig& config = plan.config;
    print_out("trace {} ({} frames of {}x{} x {} views, recorded with {} on {} devices)\n",
              o->trace_path, trace.frames.size(), trace.frames[0].shape.width,
              trace.frames[0].shape.height, trace.frames[0].shape.views, trace.balancer,
              trace.devices.size());
    print_out(
        "simulated (virtual time, emulated devices and link): {} frames, warm-up {}, speeds {}, "
        "slowdown {}, noise {}, link {}, results {} ({:.3g} bytes a pixel)\n",
        frames, config.warmup, o->speeds, o->slowdown, o->noise, o->link, o->results,
        config.link.bytes_per_pixel);
    print_out("{:>7}  {:<16} {:>12} {:>12} {:>10} {:>10} {:>10}\n", "devices", "balancer",
              "frame ms", "ideal ms", "efficiency", "imbalance", "deviation");
    const auto start = std::chrono::steady_clock::now();
    const std::vector<balance::StudyResult> results = study::run_simulation(
        trace, plan, [](const std::string& spec, const balance::StudyResult& r) {
          print_out("{:>7}  {:<16} {:>12.3f} {:>12.3f} {:>10.3f} {:>9.1f}% {:>9.1f}%\n", r.devices,
                    spec.substr(0, 16), r.mean_frame_ms, r.mean_ideal_ms, r.efficiency,
                    100 * r.mean_imbalance, 100 * r.mean_deviation);
        });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    print_out("({} simulations in {:.2f} s of real time)\n", results.size(), seconds);
    if (!o->json_path.empty())
      write_file_atomically(o->json_path,
                            study::dump_json(study::simulation_to_json(*o, plan, results)) + "\n");
    if (!o->plot_path.empty()) {
      std::vector<study::ScalingSeries> series(specs.size());
      for (size_t k = 0; k < specs.size(); ++k) {
        series[k].name = specs[k];
        for (size_t c = 0; c < counts.size(); ++c) {
          const auto& r = results[c * specs.size() + k];
          series[k].points.push_back({double(r.devices), r.efficiency});
        }
      }
      study::write_scaling_svg(
          o->plot_path,
          fmt::format("efficiency (ideal / simulated frame time) — {}, speeds {}, "
                      "link {} (emulated, virtual time)",
                      o->trace_path, o->speeds, o->link),
          series);
    }
    return 0;
  };
}

}  // namespace multiray::app
