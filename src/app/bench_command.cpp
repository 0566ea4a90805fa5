// `multiray bench`: every balancer on the same frames, in one process, with the ideal
// frame time measured by each device rendering sampled frames alone.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/report_plots.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "device/work_list.h"

namespace multiray::app {

namespace {

struct BenchOptions {
  std::string balancers = "uniform,static,queue,semi-static,dlb,hybrid";
  std::string json_path;
  std::string report_dir;
  int warmup = 10;
  int ideal_frames = 10;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// Emulated speeds as the perturbations set them at `frame`.
std::vector<double> speeds_at(const Setup& s, const std::vector<double>& initial, int frame) {
  std::vector<double> v = initial;
  for (const Perturbation& p : s.perturbations)
    if (p.frame <= frame) v[size_t(p.device)] = p.speed;
  return v;
}

// Frames on which the ideal is measured: `count` frames spread evenly over
// [first, frames - 1].
std::vector<int> ideal_frames(int first, int frames, int count) {
  std::vector<int> out;
  const int span = frames - first;
  count = std::min(count, span);
  for (int k = 0; k < count; ++k) out.push_back(first + int(int64_t(k) * span / count));
  return out;
}

// Ideal frame time of each frame in `which`: 1 / sum_i(1 / T_i), each T_i measured by
// device i rendering the whole frame alone (on a thread of its own, as in the engine, so
// pinning and quotas apply to that thread only).
std::vector<double> measure_ideal_ms(Setup& s, const std::vector<double>& initial,
                                     const std::vector<int>& which, nlohmann::json& detail) {
  std::vector<double> ideal;
  for (const int f : which) {
    const auto speeds = speeds_at(s, initial, f);
    std::vector<Framebuffer> out(size_t(s.rig.view_count()),
                                 Framebuffer(s.res.width, s.res.height));
    const Setup::FrameInput in = s.frame_input(f);
    FrameJob job{in.views, s.settings, &out};
    double inv = 0;
    nlohmann::json alone = nlohmann::json::array();
    for (size_t i = 0; i < s.devices.size(); ++i) {
      s.devices[i]->set_emulated_speed(speeds[i]);
      std::vector<WorkUnit> all_views;
      for (uint32_t v = 0; v < uint32_t(job.views.size()); ++v)
        all_views.push_back(WorkUnit{{0, 0, s.res.width, s.res.height}, v, v});
      ListWorkSource whole(all_views);
      DeviceReport r;
      std::thread([&] { r = s.devices[i]->render(job, whole, int(i)); }).join();
      if (r.failed) throw DeviceError("device " + std::to_string(i) + " failed: " + r.error);
      inv += 1.0 / std::max(r.wall_ms, 1e-6);
      alone.push_back(r.wall_ms);
    }
    detail.push_back({{"frame", f}, {"device_alone_ms", alone}, {"ideal_ms", 1.0 / inv}});
    ideal.push_back(1.0 / inv);
  }
  for (size_t i = 0; i < s.devices.size(); ++i) s.devices[i]->set_emulated_speed(initial[i]);
  return ideal;
}

struct RunSummary {
  double mean_frame_ms = 0, mean_imbalance = 0, mean_deviation = 0, efficiency = 0;
  double speedup = 0;
  int recovery_frames = -1;  // frames after the first perturbation until imbalance < 5%
};

}  // namespace

Runner add_bench_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "bench", "Run several balancers on the same frames and compare how evenly devices finish");
  auto o = std::make_shared<CommonOptions>();
  auto b = std::make_shared<BenchOptions>();
  o->frames = 100;
  o->camera_path = "orbit";
  o->spp = 4;
  add_common_options(*cmd, *o);
  cmd->add_option("--balancers", b->balancers, "Comma-separated balancer specs to compare")
      ->capture_default_str();
  cmd->add_option("--json", b->json_path, "Write all measurements as JSON to this file");
  cmd->add_option("--report", b->report_dir,
                  "Folder for plots: <balancer>_timeline.svg, <balancer>_partition.png");
  cmd->add_option("--warmup", b->warmup, "Frames left out of the summary (balancers settling)")
      ->capture_default_str();
  cmd->add_option("--ideal-frames", b->ideal_frames,
                  "Frames (spread over those after --warmup) on which each device is timed alone; "
                  "efficiency = sum of their ideal times / sum of their actual frame times")
      ->capture_default_str();
  return [=]() -> int {
    const auto specs = split_list(b->balancers);
    if (specs.empty()) throw InputError("--balancers is empty");
    if (b->warmup < 0 || b->warmup >= o->frames)
      throw InputError("--warmup must be in 0.." + std::to_string(o->frames - 1));
    if (b->ideal_frames < 1 || b->ideal_frames > 1000)
      throw InputError("--ideal-frames must be in 1..1000");
    Setup s = make_setup(*o);
    std::vector<std::string> mapped;
    for (const auto& spec : specs) mapped.push_back(apply_mapping(spec, o->mapping));
    for (const auto& spec : mapped)
      make_balancer_or_throw(spec, int(s.devices.size()));  // fail early
    if (!b->report_dir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(b->report_dir, ec);
      if (ec)
        throw InputError("cannot create report folder '" + b->report_dir + "': " + ec.message());
    }
    for (const auto& n : s.notes) fmt::print(stderr, "multiray: note: {}\n", n);
    std::vector<double> initial;
    std::vector<std::string> labels;
    for (size_t i = 0; i < s.devices.size(); ++i) {
      const DeviceInfo& info = s.devices[i]->info();
      initial.push_back(info.emulated_speed);
      labels.push_back(fmt::format("{}: {}", i, info.name));
    }
    fmt::print(
        "scene {}, {}x{} x {} views, {} integrator, {} sampling ({} spp), {} frames, camera path "
        "{}\n",
        s.scene->name, s.res.width, s.res.height, s.rig.view_count(), o->integrator, o->sampling,
        o->sampling == "adaptive" ? fmt::format("{} on edges, 1 elsewhere", o->edge_spp)
        : o->sampling == "foveated"
            ? fmt::format("{:g} at the gaze, {:g} in the periphery, "
                          "{} pattern samples, gaze path {}",
                          o->foveation.fovea_spp, o->foveation.periphery_spp,
                          s.pattern->offsets.size(), o->gaze_path)
            : std::to_string(o->spp),
        o->frames, o->camera_path);
    for (const auto& l : labels) fmt::print("  device {}\n", l);

    nlohmann::json ideal_detail = nlohmann::json::array();
    const std::vector<int> sampled = ideal_frames(b->warmup, o->frames, b->ideal_frames);
    const std::vector<double> ideal = measure_ideal_ms(s, initial, sampled, ideal_detail);
    double ideal_sum = 0;
    for (double v : ideal) ideal_sum += v;
    const double ideal_ms = ideal_sum / double(ideal.size());
    fmt::print("ideal frame time {:.1f} ms (mean over {} frames, each device timed alone)\n",
               ideal_ms, ideal.size());

    nlohmann::json runs = nlohmann::json::array();
    std::vector<RunSummary> summaries;
    std::vector<Vec3> first_image;
    for (size_t run = 0; run < specs.size(); ++run) {
      const std::string& spec = specs[run];
      for (size_t i = 0; i < s.devices.size(); ++i) s.devices[i]->set_emulated_speed(initial[i]);
      Engine engine(s.device_ptrs(), make_balancer_or_throw(mapped[run], int(s.devices.size())));
      engine.set_perturbations(s.perturbations);
      std::vector<FrameRecord> recs;
      std::vector<double> sampling_ms;  // host set-up of irregular sampling, outside frame_ms
      for (int f = 0; f < o->frames; ++f) {
        if (stderr_is_tty()) fmt::print(stderr, "\r{}: frame {}/{} ", spec, f + 1, o->frames);
        const Setup::FrameInput in = s.frame_input(f);
        sampling_ms.push_back(in.sampling_ms);
        recs.push_back(engine.render_frame(f, in.views, s.settings));
        for (const auto& m : recs.back().messages)
          fmt::print(stderr, "\nmultiray: warning: {}\n", m);
        if (f == o->frames / 2 && !b->report_dir.empty())
          write_partition_png(
              fmt::format("{}/{}_partition.png", b->report_dir, engine.balancer().name()),
              s.res.width, s.res.height, engine.last_rendered());
      }
      if (stderr_is_tty()) fmt::print(stderr, "\r\033[K");
      bool same_image = true;
      if (first_image.empty())
        first_image = engine.images()[0].pixels;
      else
        same_image = std::memcmp(first_image.data(), engine.images()[0].pixels.data(),
                                 first_image.size() * sizeof(Vec3)) == 0;
      RunSummary sum;
      int counted = 0;
      for (const auto& r : recs)
        if (r.frame >= b->warmup) {
          sum.mean_frame_ms += r.frame_ms, sum.mean_imbalance += r.imbalance;
          sum.mean_deviation += r.deviation, ++counted;
        }
      sum.mean_frame_ms /= counted, sum.mean_imbalance /= counted, sum.mean_deviation /= counted;
      // Efficiency on the frames whose ideal was measured (frame cost varies along a path).
      double actual_sum = 0;
      for (const int f : sampled) actual_sum += recs[size_t(f)].frame_ms;
      sum.efficiency = ideal_sum / actual_sum;
      if (!s.perturbations.empty()) {
        const int p = s.perturbations.front().frame;
        for (int f = p; f < o->frames; ++f)
          if (recs[size_t(f)].imbalance < 0.05) {
            sum.recovery_frames = f - p;
            break;
          }
      }
      summaries.push_back(sum);
      nlohmann::json frames = nlohmann::json::array();
      for (const auto& r : recs) {
        frames.push_back(frame_to_json(r));
        frames.back()["sampling_ms"] = sampling_ms[size_t(r.frame)];
      }
      runs.push_back({{"balancer", engine.balancer().spec()},
                      {"devices", devices_to_json(s.devices)},
                      {"image_matches_first_run", same_image},
                      {"frames", frames},
                      {"summary",
                       {{"from_frame", b->warmup},
                        {"mean_frame_ms", sum.mean_frame_ms},
                        {"mean_imbalance", sum.mean_imbalance},
                        {"mean_deviation", sum.mean_deviation},
                        {"ideal_ms", ideal_ms},
                        {"ideal_frames", sampled},
                        {"efficiency", sum.efficiency},
                        {"recovery_frames", sum.recovery_frames}}}});
      if (!b->report_dir.empty())
        write_timeline_svg(
            fmt::format("{}/{}_timeline.svg", b->report_dir, engine.balancer().name()),
            fmt::format("{} — {} ({}x{}, {} spp)", engine.balancer().spec(), s.scene->name,
                        s.res.width, s.res.height, o->spp),
            recs, labels);
      if (!same_image)
        fmt::print(stderr, "multiray: warning: {} produced a different image than {}\n", spec,
                   specs[0]);
    }
    // Speedup against uniform, when uniform was run.
    double uniform_ms = 0;
    for (size_t k = 0; k < specs.size(); ++k)
      if (runs[k]["balancer"].get<std::string>().rfind("uniform", 0) == 0)
        uniform_ms = summaries[k].mean_frame_ms;
    fmt::print("\n{:<44} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "balancer (frames >= warmup)",
               "frame ms", "imbalance", "deviation", "efficiency", "speedup", "recovery");
    for (size_t k = 0; k < specs.size(); ++k) {
      RunSummary& sm = summaries[k];
      sm.speedup = uniform_ms > 0 ? uniform_ms / sm.mean_frame_ms : 0.0;
      runs[k]["summary"]["speedup_vs_uniform"] =
          uniform_ms > 0 ? nlohmann::json(sm.speedup) : nlohmann::json();
      fmt::print("{:<44} {:>10.1f} {:>9.1f}% {:>9.1f}% {:>10.3f} {:>9} {:>9}\n",
                 runs[k]["balancer"].get<std::string>(), sm.mean_frame_ms, 100 * sm.mean_imbalance,
                 100 * sm.mean_deviation, sm.efficiency,
                 uniform_ms > 0 ? fmt::format("{:.2f}x", sm.speedup) : "-",
                 sm.recovery_frames >= 0 ? std::to_string(sm.recovery_frames) : "-");
    }
    bool emulated = false;
    for (double v : initial) emulated |= v < 1;
    if (emulated || !s.perturbations.empty())
      fmt::print(
          "(device speeds below 1 are emulated: the device idles after each piece of work)\n");
    if (!b->json_path.empty()) {
      nlohmann::json doc{{"scene", s.scene->name},
                         {"resolution", {s.res.width, s.res.height}},
                         {"views", s.rig.view_count()},
                         {"spp", o->spp},
                         {"integrator", o->integrator},
                         {"sampling", o->sampling},
                         {"frames", o->frames},
                         {"camera_path", o->camera_path},
                         {"timing",
                          "device_ms measured inside each device (steady_clock); frame_ms by the "
                          "engine around all devices"},
                         {"ideal", ideal_detail},
                         {"runs", runs}};
      std::ofstream out(b->json_path);
      if (!out) throw InputError("cannot write '" + b->json_path + "'");
      out << doc.dump(1) << "\n";
    }
    return 0;
  };
}

}  // namespace multiray::app
