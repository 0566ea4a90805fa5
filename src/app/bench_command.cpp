// `multiray bench`: every balancer on the same frames, in one process and interleaved
// frame by frame, with the ideal frame time measured by each device rendering sampled
// frames alone.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/bench_summary.h"
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
  int ideal_frames = 20;
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

// Ideal time of one frame: 1 / sum_i(1 / T_i), each T_i measured by device i rendering
// all of `in` alone at the emulated `speeds` of that frame (on a thread of its own, as in
// the engine, so pinning and quotas apply to that thread only). Leaves the devices at
// `speeds`.
double measure_ideal_ms(Setup& s, const Setup::FrameInput& in, const std::vector<double>& speeds,
                        nlohmann::json& detail) {
  std::vector<Framebuffer> out(in.views.size(), Framebuffer(s.res.width, s.res.height));
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
  detail.push_back(
      {{"frame", in.views[0].frame}, {"device_alone_ms", alone}, {"ideal_ms", 1.0 / inv}});
  return 1.0 / inv;
}

// One balancer's engine and what it measured.
struct Run {
  std::string spec;
  std::unique_ptr<Engine> engine;
  std::vector<FrameRecord> recs;
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
                  "efficiency = sum of ideal times (interpolated between those frames) / sum of "
                  "actual frame times, over the frames after --warmup")
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
        "scene {}, {}x{} x {} views, {} integrator, {} sampling ({}), {} frames, camera path "
        "{}\n",
        s.scene->name, s.res.width, s.res.height, s.rig.view_count(), o->integrator, o->sampling,
        o->sampling == "adaptive" ? fmt::format("{} spp on edges, 1 elsewhere", o->edge_spp)
        : o->sampling == "foveated"
            ? fmt::format("{:g} spp at the gaze, {:g} in the periphery, "
                          "{} pattern samples, gaze path {}",
                          o->foveation.fovea_spp, o->foveation.periphery_spp,
                          s.pattern->offsets.size(), o->gaze_path)
            : std::to_string(o->spp) + " spp",
        o->frames, o->camera_path);
    for (const auto& l : labels) fmt::print("  device {}\n", l);

    // Every balancer renders frame f before any renders frame f + 1 (and the ideal of a
    // sampled frame is measured right before it): load from other programs on a shared
    // machine then hits all balancers alike, so the comparison stays fair.
    const std::vector<int> sampled = ideal_frames(b->warmup, o->frames, b->ideal_frames);
    std::vector<double> ideal;
    nlohmann::json ideal_detail = nlohmann::json::array();
    std::vector<Run> runs;
    for (size_t k = 0; k < specs.size(); ++k) {
      runs.push_back(
          {mapped[k],
           std::make_unique<Engine>(s.device_ptrs(),
                                    make_balancer_or_throw(mapped[k], int(s.devices.size()))),
           {}});
      runs.back().engine->set_perturbations(s.perturbations);
    }
    std::vector<double> sampling_ms;  // host set-up of irregular sampling, outside frame_ms
    for (int f = 0; f < o->frames; ++f) {
      if (stderr_is_tty()) fmt::print(stderr, "\rframe {}/{} ", f + 1, o->frames);
      const Setup::FrameInput in = s.frame_input(f);
      sampling_ms.push_back(in.sampling_ms);
      const auto speeds = speeds_at(s, initial, f);
      if (std::find(sampled.begin(), sampled.end(), f) != sampled.end())
        ideal.push_back(measure_ideal_ms(s, in, speeds, ideal_detail));
      for (Run& run : runs) {
        run.recs.push_back(run.engine->render_frame(f, in.views, s.settings));
        for (const auto& m : run.recs.back().messages)
          fmt::print(stderr, "\nmultiray: warning: {}\n", m);
        if (f == o->frames / 2 && !b->report_dir.empty())
          write_partition_png(
              fmt::format("{}/{}_partition.png", b->report_dir, run.engine->balancer().name()),
              s.res.width, s.res.height, run.engine->last_rendered());
      }
    }
    if (stderr_is_tty()) fmt::print(stderr, "\r\033[K");
    double ideal_mean = 0;
    for (double v : ideal) ideal_mean += v / double(ideal.size());
    fmt::print("ideal frame time {:.1f} ms (mean over {} frames, each device timed alone)\n",
               ideal_mean, ideal.size());

    const int perturb_frame = s.perturbations.empty() ? -1 : s.perturbations.front().frame;
    std::vector<RunSummary> summaries;
    for (const Run& run : runs)
      summaries.push_back(summarize(run.recs, b->warmup, sampled, ideal, perturb_frame));
    add_speedups(mapped, summaries);
    print_table(mapped, summaries);
    nlohmann::json runs_json = nlohmann::json::array();
    for (size_t k = 0; k < runs.size(); ++k) {
      const Run& run = runs[k];
      const auto& img = run.engine->images()[0].pixels;
      const auto& first = runs[0].engine->images()[0].pixels;
      const bool same_image =
          std::memcmp(img.data(), first.data(), img.size() * sizeof(Vec3)) == 0;
      if (!same_image)
        fmt::print(stderr, "multiray: warning: {} produced a different image than {}\n", run.spec,
                   runs[0].spec);
      nlohmann::json frames = nlohmann::json::array();
      for (const auto& r : run.recs) {
        frames.push_back(frame_to_json(r));
        frames.back()["sampling_ms"] = sampling_ms[size_t(r.frame)];
      }
      runs_json.push_back(
          {{"balancer", run.engine->balancer().spec()},
           {"devices", devices_to_json(s.devices)},
           {"image_matches_first_run", same_image},
           {"frames", frames},
           {"summary", summary_to_json(summaries[k], b->warmup, ideal_mean, sampled)}});
      if (!b->report_dir.empty())
        write_timeline_svg(
            fmt::format("{}/{}_timeline.svg", b->report_dir, run.engine->balancer().name()),
            fmt::format("{} — {} ({}x{}, {} spp)", run.engine->balancer().spec(), s.scene->name,
                        s.res.width, s.res.height, o->spp),
            run.recs, labels);
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
                         {"runs", runs_json}};
      std::ofstream out(b->json_path);
      if (!out) throw InputError("cannot write '" + b->json_path + "'");
      out << doc.dump(1) << "\n";
    }
    return 0;
  };
}

}  // namespace multiray::app
