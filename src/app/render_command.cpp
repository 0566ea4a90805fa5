#include <unistd.h>

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
#include "app/console.h"
#include "app/frame_spool.h"
#include "app/interrupt.h"
#include "app/progress.h"
#include "app/stats_json.h"
#include "app/trace_file.h"
#include "balance/registry.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/output_folder.h"

namespace multiray::app {

bool stderr_is_tty() { return isatty(STDERR_FILENO) == 1; }

namespace {

// What the progress line reads while frames finish (written by RenderOutput).
struct RenderCounters {
  std::atomic<int> frames{0};
  std::atomic<uint64_t> samples{0};
  std::atomic<uint64_t> frame_us{0};  // the finished frames' times, microseconds
};

// Writes each finished frame (PNG, EXR, quilt), prints its line, keeps its JSON record on
// disk (FrameSpool: memory stays flat however many frames) and, with --trace, its per-item
// measurements.
class RenderOutput : public FrameObserver {
 public:
  RenderOutput(const std::string& dir, bool exr, bool quiet, int columns, int frames,
               const Display& display, TraceFile* trace)
      : dir_(dir),
        records_(dir),
        exr_(exr),
        quiet_(quiet),
        columns_(columns),
        frames_(frames),
        display_(display),
        trace_(trace) {}

  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    const std::string base = fmt::format("{}/frame_{:04d}", dir_, r->frame);
    const auto& images = r->images;
    for (size_t v = 0; v < images.size(); ++v) {
      const std::string name = images.size() == 1 ? base : fmt::format("{}_view{:02d}", base, v);
      write_png(name + ".png", images[v], display_);
      if (exr_) write_exr(name + ".exr", images[v]);
    }
    if (images.size() > 1) write_png(base + "_quilt.png", make_quilt(images, columns_), display_);
    if (stderr_is_tty()) print_err("\r\033[K");
    const FrameRecord& rec = r->record;
    for (const auto& m : rec.messages) print_err("multiray: warning: {}\n", m);
    uint64_t samples = 0, rays = 0;
    for (const auto& d : rec.devices) samples += d.samples, rays += d.rays;
    // Frame-time targeting: the predicted time and the quality the frame was rendered at.
    const std::string adapted =
        rec.predicted_ms > 0 || rec.quality.step_scale != 1 || rec.quality.image_scale != 1
            ? fmt::format("  predicted {:7.1f} ms  step x{:.2f}  image x{:.2f}", rec.predicted_ms,
                          rec.quality.step_scale, rec.quality.image_scale)
            : "";
    // Reprojected sampling: the share of the other views' pixels path-traced as holes.
    const std::string holes =
        r->reprojection ? fmt::format("  holes {:4.1f}%", 100.0 * r->reprojection->hole_fraction())
                        : "";
    if (!quiet_)
      print_out(
          "frame {:4d}  {:9.1f} ms  {:7.2f} Msamples/s  {:7.2f} Mrays/s  imbalance {:5.1f}%{}{}  "
          "-> {}.png\n",
          r->frame, rec.frame_ms, samples / rec.frame_ms / 1e3, rays / rec.frame_ms / 1e3,
          100.0 * rec.imbalance, adapted, holes, base + (images.size() > 1 ? "_quilt" : ""));
    nlohmann::json record = frame_to_json(rec);
    record["sampling_ms"] = r->sampling_ms;
    if (r->reprojection)
      record["reprojection"] =
          reprojection_to_json(r->reprojection->references, r->reprojection->hole_fraction());
    uint64_t hash = 0xcbf29ce484222325ull;
    for (const Framebuffer& img : images) hash = image_hash(img, hash);
    record["image_hash"] = fmt::format("{:016x}", hash);
    records_.add(record);
    if (trace_) trace_->frame(r->stats);
    counters_.samples += samples;
    counters_.frame_us += uint64_t(std::max(0.0, rec.frame_ms) * 1e3);
    counters_.frames += 1;
  }

  const RenderCounters& counters() const { return counters_; }

  // Writes stats.json: `head` with every frame's record as "frames".
  void write_stats(const nlohmann::json& head) { records_.write(dir_ + "/stats.json", head); }

 private:
  std::string dir_;
  FrameSpool records_;
  RenderCounters counters_;
  bool exr_, quiet_;
  int columns_, frames_;
  Display display_;
  TraceFile* trace_;
};

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
  auto balancer = std::make_shared<std::string>("hybrid");
  auto trace_path = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  add_common_options(*cmd, *o);
  auto overwrite = std::make_shared<bool>(false);
  cmd->add_option("-o,--out", *out_dir,
                  "Output folder (created if missing). A folder with an earlier run's outputs "
                  "(stats.json, frame_*) is refused unless --overwrite is given")
      ->capture_default_str();
  cmd->add_flag("--overwrite", *overwrite,
                "Replace an earlier run's outputs in --out (its stats.json and frame_* files "
                "are deleted first; other files are kept)");
  cmd->add_flag("--exr", *exr,
                "Also write linear-light OpenEXR files (raw radiance: no --exposure, no --tone)");
  auto exposure = std::make_shared<double>(0.0);
  auto tone = std::make_shared<std::string>("auto");
  cmd->add_option("--exposure", *exposure,
                  "Exposure of the PNG files in stops, [-20, 20]: radiance is multiplied by "
                  "2^EV before the tone curve")
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
  cmd->add_flag("-q,--quiet", *quiet,
                "No per-frame lines, and no progress lines when stderr is not a terminal");
  return [=]() -> int {
    Display display;
    display.exposure_ev = parse_exposure(*exposure);
    const bool volume_input = is_volume_input(o->scene_path, o->volume);
    display.tone = parse_tone(*tone, volume_input);
    Run s;
    int worker_exit = 0;
    std::vector<std::string> specs{*balancer};  // --mapping applied by start_run
    std::unique_ptr<OutputFolder> folder;       // held (locked) until the run has ended
    std::unique_ptr<Session> session = start_run(
        s, *o, specs, "--balancer", &worker_exit,
        [&] {
          if (!trace_path->empty()) check_output_file(*trace_path, "--trace");
          folder = std::make_unique<OutputFolder>(*out_dir, *overwrite);
        },
        [](const Run& run) {
          if (run.volume && run.volume->modes().size() > 1)
            throw InputError("--adapt: render takes one mode (bench compares several)");
        });
    if (!session) return worker_exit;
    std::unique_ptr<TraceFile> trace;
    if (!trace_path->empty())
      trace = std::make_unique<TraceFile>(*trace_path, session->engine(0).balancer().spec(),
                                          s.devices);
    RenderOutput output(*out_dir, *exr, *quiet, s.views->rig().columns, o->frames, display,
                        trace.get());
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
    nlohmann::json settings = settings_to_json(*o, s, command_line);
    settings["balancer"] = specs[0];  // as asked; "balancer" below has every parameter
    settings["exposure_ev"] = display.exposure_ev;
    settings["tone"] = display.tone == ToneCurve::Filmic ? "filmic" : "clamp";
    settings["exr"] = *exr;
    nlohmann::json doc{{"scene", s.scene->name},
                       {"settings", settings},
                       {"devices", devices_to_json(s.devices)},
                       {"balancer", session->engine(0).balancer().spec()},
                       {"views", s.views->rig().view_count()},
                       {"frames_requested", o->frames}};
    if (interrupted) doc["interrupted_by"] = signal_name;
    output.write_stats(doc);
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
