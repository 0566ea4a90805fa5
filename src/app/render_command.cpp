#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_target.h"
#include "app/progress.h"
#include "app/render_output.h"
#include "balance/registry.h"
#include "balance/targeting.h"
#include "core/console.h"
#include "core/error.h"
#include "core/feature_buffers.h"
#include "core/file_io.h"
#include "core/output_folder.h"
#include "render/denoise.h"
#include "run/ar_setup.h"
#include "run/interrupt.h"
#include "run/parse_options.h"
#include "run/sequence.h"
#include "study/stats_json.h"
#include "study/trace_file.h"

namespace multiray::app {

namespace {

// Progress of a render (app/progress.h): on a terminal, a line redrawn five times a second;
// otherwise (a pipe, a log file), unless --quiet, a line every 10 s, so that a long run
// is never silent for long.
class ProgressLine {
 public:
  ProgressLine(const Session& session, int frames, const RenderCounters& counters, bool quiet) {
    const bool terminal = stderr_is_tty();
    if (!terminal && quiet) return;
    thread_ = std::thread([this, &session, &counters, frames, terminal] {
      const auto start = std::chrono::steady_clock::now();
      auto last_line = start;
      while (!stop_.load()) {
        {
          std::unique_lock<std::mutex> lock(mutex_);
          wake_.wait_for(lock, std::chrono::milliseconds(200), [this] { return stop_.load(); });
        }
        if (stop_) break;
        const auto now = std::chrono::steady_clock::now();
        if (!terminal && now - last_line < std::chrono::seconds(10)) continue;
        last_line = now;
        ProgressSnapshot p;
        p.frames_done = counters.frames.load();
        p.frames_total = frames;
        p.current = session.progress();
        p.elapsed_s = std::chrono::duration<double>(now - start).count();
        p.samples = double(counters.samples.load());
        p.samples_elapsed_s = double(counters.frame_us.load()) / 1e6;
        if (terminal)
          print_err("\r{}\033[K", progress_line(p, true));
        else
          print_err("{}\n", progress_line(p, false));
      }
      if (terminal) print_err("\r\033[K");
    });
  }
  ~ProgressLine() {
    stop_ = true;
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace

Runner add_render_command(CLI::App& app, const std::vector<std::string>& command_line) {
  auto* cmd = app.add_subcommand("render", "Render frames to PNG (and EXR) files");
  auto o = std::make_shared<RunConfig>();
  auto out_dir = std::make_shared<std::string>("out");
  auto exr = std::make_shared<bool>(false);
  auto balancer = std::make_shared<std::string>("auto");
  auto trace_path = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  add_common_options(*cmd, *o);
  auto overwrite = std::make_shared<bool>(false);
  auto* out_option =
      cmd->add_option("-o,--out", *out_dir,
                      "Where to write: a folder (frame_NNNN.png, stats.json), one file for one "
                      "frame (render.png, render.exr), or a pattern whose run of # is the frame "
                      "number (shot_####.png; stats in shot.stats.json). A .exr name writes "
                      "linear OpenEXR only. Not given: out/, or out-2/, out-3/, ... when out/ "
                      "holds an earlier run. Files named by -o (a file or a pattern) are "
                      "replaced; a folder's earlier outputs are refused unless --overwrite")
          ->capture_default_str();
  cmd->add_flag("--overwrite", *overwrite,
                "Replace an earlier run's outputs at -o (exactly the files this run would write "
                "and its stats file are deleted first; other files are kept)");
  cmd->add_flag("--exr", *exr,
                "Also write linear-light OpenEXR files (raw radiance: no --exposure, no --tone)");
  auto exposure = std::make_shared<std::string>("auto");
  auto tone = std::make_shared<std::string>("auto");
  cmd->add_option("--exposure", *exposure,
                  "Exposure of the PNG files: auto (metered on the first frame's radiance to "
                  "middle grey, then held; volumes: 0) or EV in stops, [-20, 20]: radiance is "
                  "multiplied by 2^EV before the tone curve")
      ->capture_default_str();
  cmd->add_option("--tone", *tone,
                  "Tone curve of the PNG files: filmic (ACES fit by Narkowicz 2015; highlights "
                  "roll off), clamp (values above 1 clip), or auto: filmic for meshes, clamp for "
                  "volumes (the raycaster already writes display colours)")
      ->capture_default_str();
  cmd->add_option("--balancer", *balancer,
                  "How work is split between devices, NAME[:key=value]... (docs/balancers.md):\n" +
                      balance::balancer_help())
      ->capture_default_str();
  cmd->add_option("--trace", *trace_path,
                  "Write every work item's device, view, rect, samples, busy and wall time to "
                  "this file (format: docs/traces.md), for `multiray simulate` and analysis");
  auto background = std::make_shared<std::string>();
  cmd->add_option("--background", *background,
                  "Augmented reality: the real images the --ground layer is composited over, "
                  "an image or a numbered sequence whose run of # is the frame number "
                  "(frames/bg_####.png); PNG, JPEG or EXR, resized to --res when the aspect "
                  "ratio agrees. The PNGs then default to --exposure 0 --tone clamp, so the "
                  "real image comes out as it went in (docs/ar.md)");
  auto aov = std::make_shared<std::string>();
  cmd->add_option("--aov", *aov,
                  "Also write feature buffers (AOVs) of the path tracer, a comma-separated "
                  "subset of albedo, normal, depth, variance, emission, as layers of one "
                  "multi-layer OpenEXR with the beauty (albedo.R/G/B, normal.X/Y/Z, depth.Z, "
                  "variance.Y, emission.R/G/B: lights seen directly or through glass): the "
                  "frame's .exr, or <image>_aov.exr beside a PNG; for Open Image Denoise or "
                  "Blender's compositor (docs/aov.md)");
  auto denoise = std::make_shared<std::string>("auto");
  {
    std::string help =
        "Filter the image with its feature buffers after each frame (docs/noise.md, "
        "\"The denoiser\"):";
    for (const DenoiseMethodInfo& m : denoise_methods())
      help += std::string(" ") + m.name + ": " + m.help + ";";
    help.back() = '.';
    help +=
        " PNGs show the denoised image; an EXR keeps the raw beauty unless a method is "
        "named";
    cmd->add_option("--denoise", *denoise, help)->capture_default_str();
  }
  auto no_overlap = std::make_shared<bool>(false);
  cmd->add_flag("--no-denoise-overlap", *no_overlap,
                "Filter each frame before the next one renders. By default frame N is filtered "
                "while frame N+1 renders: the same images, and the filter's time hidden where "
                "the devices are not the host's cores (docs/noise.md, \"Beside the rendering\")");
  auto overlay = std::make_shared<bool>(false);
  cmd->add_flag("--overlay", *overlay,
                "Also write a picture of how each frame was split: <image>_split.png, the frame "
                "with each device's pieces tinted in its colour and a legend (share of the "
                "samples, busy time)");
  cmd->add_flag("-q,--quiet", *quiet,
                "No per-frame lines, and no progress lines when stderr is not a terminal");
  const CLI::Option* frames_option = cmd->get_option("--frames");
  return [=]() -> int {
    // A sequence file that says how many frames it lasts sets --frames unless it is given.
    if (!frames_option->count() && !o->volume.sequence.empty())
      if (const int n = load_sequence(o->volume.sequence).frames; n > 0) o->frames = n;
    // So do poses: one frame each.
    if (!frames_option->count() && !o->poses.empty()) o->frames = pose_count(o->poses);
    if (!aov->empty()) o->aovs = parse_aov_list(*aov, "--aov");
    if (!background->empty() && o->ground.empty())
      throw InputError("--background needs --ground (the plane standing for the real ground)");
    Display display;
    const bool volume_input = is_volume_input(o->scene_path, o->volume);
    const bool ar = !background->empty();
    const bool fixed_exposure = *exposure != "auto" || volume_input || ar;
    if (*exposure != "auto") {
      const std::optional<double> ev = parse_number(*exposure);
      if (!ev)
        throw InputError("--exposure '" + *exposure + "' must be auto or stops in [-20, 20]");
      display.exposure_ev = parse_exposure(*ev);
    }
    display.tone = parse_tone(*tone == "auto" && ar ? "clamp" : *tone, volume_input);
    const OutputTarget target = parse_output_target(
        out_option->count() ? *out_dir : first_free_folder(*out_dir), o->frames, *exr);
    o->denoise = *denoise;
    o->png_output = target.png;
    Run s;
    int worker_exit = 0;
    std::vector<std::string> specs{*balancer};            // --mapping applied by start_run
    std::unique_ptr<OutputFolder> folder;                 // held (locked) until the run has ended
    std::shared_ptr<const BackgroundImages> backgrounds;  // --background
    std::unique_ptr<Session> session = start_run(
        s, *o, specs, "--balancer", &worker_exit,
        [&] {
          if (!trace_path->empty()) check_output_file(*trace_path, "--trace");
          if (ar) {  // every frame's file, before the scene loads
            const Resolution res = parse_resolution(o->resolution);
            backgrounds = std::make_shared<const BackgroundImages>(*background, res.width,
                                                                   res.height, o->frames);
          }
          // Files named by -o (one file, or a pattern of numbered files) are replaced
          // (atomically, as every image is written), as Cycles' -o and pbrt's --outfile do;
          // only a folder holding an earlier run's frames is protected. (--overwrite still
          // removes a pattern's earlier files first: a shorter run leaves none behind.)
          const bool named = target.pattern && !*overwrite;
          folder = std::make_unique<OutputFolder>(
              target.dir, *overwrite, "-o",
              [&](const std::string& n) { return !named && target.owns(n); });
        },
        [&](const Run& run) {
          if (run.volume && run.volume->modes().size() > 1)
            throw InputError("--adapt: render takes one mode (bench compares several)");
          // The largest background, decoded in turn with every frame while the scene's
          // images are kept: charged with them against --max-memory before anything renders.
          if (backgrounds && run.reserve_image) {
            const BackgroundImages::Largest& b = backgrounds->largest();
            run.reserve_image("--background '" + b.path + "' (" + std::to_string(b.width) + " x " +
                                  std::to_string(b.height) + " pixels)",
                              0, b.bytes);
          }
        });
    if (!session) return worker_exit;
    session->set_denoise_overlap(!*no_overlap);  // frame N filtered while frame N+1 renders
    const auto auto_choice = report_auto_choice(s, specs[0], "--balancer", *quiet);
    std::unique_ptr<study::TraceFile> trace;
    if (!trace_path->empty())
      trace = std::make_unique<study::TraceFile>(*trace_path, session->engine(0).balancer().spec(),
                                                 s.devices);
    if (!out_option->count() && target.dir != *out_dir && !*quiet)
      print_err("multiray: note: {}/ holds an earlier run; writing to {}/ (-o chooses)\n",
                *out_dir, target.dir);
    RenderOutput output(target, fixed_exposure, *quiet, s.views->rig().columns, display,
                        trace.get());
    if (o->volume.target_ms > 0) {
      balance::TargetingConfig targeting;  // the bounds build_run checked
      targeting.space = balance::parse_adapt_space(o->volume.adapt_space);
      output.set_targeting(o->volume.target_ms, balance::lowest_cost(targeting));
    }
    std::vector<std::string> names;
    for (const auto& d : s.devices) names.push_back(d->info().spec);
    output.set_device_names(std::move(names));
    if (*overlay) output.set_overlay();
    output.set_aovs(o->aovs);
    // The raw beauty stays in the EXR unless a method was named (not auto).
    output.set_denoised_exr(*denoise != "auto" && s.denoise != DenoiseMethod::none);
    output.set_background(backgrounds);
    int done = 0;
    int interrupted = 0;
    std::string signal_name;
    {
      InterruptWatch watch(*session);
      ProgressLine progress(*session, o->frames, output.counters(), *quiet);
      done = session->run(0, o->frames, output);
      interrupted = watch.signal();
      signal_name = watch.signal_name();
    }
    nlohmann::json settings = study::settings_to_json(*o, s, command_line);
    settings["balancer"] = specs[0];  // as asked; "balancer" below has every parameter
    settings["exposure_ev"] = output.exposure_ev();
    settings["exposure"] = output.metered() ? "auto" : "fixed";
    settings["output"] = target.pattern ? *out_dir : target.dir;
    settings["tone"] = display.tone == ToneCurve::Filmic ? "filmic" : "clamp";
    settings["exr"] = target.exr;
    settings["background"] = ar ? nlohmann::json(*background) : nlohmann::json(nullptr);
    nlohmann::json doc{{"scene", s.scene->name},
                       {"settings", settings},
                       {"devices", study::devices_to_json(s.devices)},
                       {"balancer", session->engine(0).balancer().spec()},
                       {"views", s.views->rig().view_count()},
                       {"frames_requested", o->frames}};
    if (auto_choice)
      doc["balancer_auto"] = {{"spec", auto_choice->spec}, {"reason", auto_choice->reason}};
    if (interrupted) doc["interrupted_by"] = signal_name;
    output.write_stats(doc);
    if (!*quiet) print_out("{}", output.balance_summary());
    // After stats.json, so that a failed trace (a full disk) loses only the trace.
    if (trace) trace->close();
    if (interrupted) {
      print_err(
          "multiray: interrupted by {} after {} of {} frames; their images and "
          "stats.json are complete\n",
          signal_name, done, o->frames);
      return 128 + interrupted;
    }
    return 0;
  };
}

}  // namespace multiray::app
