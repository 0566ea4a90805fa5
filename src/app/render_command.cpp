#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/interrupt.h"
#include "app/stats_json.h"
#include "app/trace_file.h"
#include "balance/registry.h"
#include "core/error.h"
#include "core/file_io.h"
#include "render/kernel.h"

namespace multiray::app {

bool stderr_is_tty() { return isatty(STDERR_FILENO) == 1; }

void add_common_options(CLI::App& cmd, CommonOptions& o) {
  cmd.add_option("scene", o.scene_path,
                 "Scene file (.gltf, .glb, .obj, .ply; .fbx, .dae, .3ds, .stl, .off, .blend and "
                 "more through assimp, see docs/scene-formats.md) or volume (.nhdr, .nrrd, or "
                 "raw with --raw); omitted: the built-in Cornell box");
  cmd.add_option("--res", o.resolution, "Image size WIDTHxHEIGHT")->capture_default_str();
  cmd.add_option(
         "--spp", o.spp,
         "Samples per pixel; 0: " + std::to_string(o.mesh_spp) + " for meshes, 1 for volumes")
      ->capture_default_str();
  cmd.add_option("--bounces", o.bounces, "Maximum scattering events per path")
      ->capture_default_str();
  cmd.add_option("--frames", o.frames, "Number of frames to render")->capture_default_str();
  cmd.add_option("--camera", o.camera,
                 "Camera as ex,ey,ez,tx,ty,tz,ux,uy,uz,fov (eye, target, up, vertical fov in "
                 "degrees); default: the scene's first camera, else a three-quarter view from "
                 "outside that frames the scene's bounding box (see --up), or a straight view "
                 "into a box that is open on one side");
  cmd.add_option("--up", o.up,
                 "The scene's up axis for the default camera and orbits: x, y or z, optionally "
                 "signed (+z, -y); auto: y for meshes (glTF's convention), z for volumes")
      ->capture_default_str();
  cmd.add_option("--camera-path", o.camera_path,
                 "Animation: fixed, orbit (100 frames per turn), orbit:PERIOD, or a keyframe "
                 "JSON file {\"keyframes\":[{\"frame\":0,\"eye\":[..],\"target\":[..],\"up\":[..],"
                 "\"fov\":45},...]}")
      ->capture_default_str();
  cmd.add_option("--devices", o.devices,
                 "Comma-separated devices, each TYPE[:KEY=VALUE...], e.g. "
                 "cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.33. cpu keys: threads "
                 "(0 = all), cores (0, 0+1, 0-3), speed (emulated slowdown, (0,1]), quota "
                 "(real cgroup throttle, (0,1] of a core), tile. opencl[:N] (N as `multiray "
                 "devices` lists) keys: speed, tile, wg (work-group size), cores (pin the "
                 "driving thread). With PoCL, POCL_DEVICES=\"basic basic\" gives two independent "
                 "one-core devices opencl:0 and opencl:1; POCL_MAX_PTHREAD_COUNT=N limits its "
                 "default pthread device to N threads")
      ->capture_default_str();
  cmd.add_option(
         "--env", o.env,
         "Light from outside the scene: a constant sky radiance V or R,G,B, or an "
         "equirectangular map FILE.hdr / FILE.exr (top row = up, see --up); auto = the "
         "scene's own, or daylight (a white sky of 0.3 and, with --sun auto, a sun; a sky of 1 "
         "without) when the "
         "scene has no light but emissive textures. The sky is sampled by next-event "
         "estimation with MIS")
      ->capture_default_str();
  cmd.add_option("--env-scale", o.env_scale, "Multiplies an --env map's radiance")
      ->capture_default_str();
  cmd.add_option(
         "--sun", o.sun,
         "A sun: auto (with the default daylight of a scene without lights: "
         "-40,55,3), off, or AZIMUTH,ELEVATION[,IRRADIANCE[,DIAMETER]], degrees round the up "
         "axis from the front towards the right and above the horizon (as the default "
         "camera's view), irradiance at normal incidence in W/m^2 in scene units "
         "(default 3; a white sky of 1 gives pi), angular diameter in degrees (0.53)")
      ->capture_default_str();
  cmd.add_option("--seed", o.seed, "Seed for all random numbers")->capture_default_str();
  cmd.add_flag("--allow-outside-paths", o.allow_outside_paths,
               "Let a scene file name files outside its own folder (buffers, images, material "
               "libraries); by default they are refused, with a warning or an error. Only "
               "regular files are ever read");
  cmd.add_option("--max-memory", o.max_memory,
                 "Refuse runs estimated to need more memory than this: auto (half of physical "
                 "memory) or a size such as 8G or 512M")
      ->capture_default_str();
  cmd.add_option("--views", o.views,
                 "Light-field grid of parallel views KxL (e.g. 3x3, 5x5), following the camera "
                 "path")
      ->capture_default_str();
  cmd.add_option("--view-spacing", o.view_spacing, "Distance between grid views (scene units)")
      ->capture_default_str();
  cmd.add_option("--stereo", o.stereo, "Render a stereo pair with this eye separation instead");
  cmd.add_option("--mapping", o.mapping,
                 "Multiview task mapping: strips (each device renders its share of every view's "
                 "shuffled strips) or views (whole views per device; uniform, static, dlb)");
  std::string kernels;
  for (const KernelEntry& e : cpu_kernels())
    kernels += (kernels.empty() ? "" : "; ") + e.name + ": " + e.help;
  cmd.add_option("--integrator", o.integrator,
                 "The kernel that renders; default: path for meshes, volume for volumes "
                 "(OpenCL devices: path only). " +
                     kernels);
  add_volume_options(cmd, o.volume);
  add_distributed_options(cmd, o.distributed);
  cmd.add_option("--ao-rays", o.ao_rays, "Occlusion rays per AO sample")->capture_default_str();
  cmd.add_option("--ao-distance", o.ao_distance,
                 "Occlusion range in scene units (0: 0.3 of the scene size)")
      ->capture_default_str();
  cmd.add_option("--sampling", o.sampling,
                 "uniform (--spp everywhere), adaptive (a first pass finds geometric edges; "
                 "edge pixels get --edge-spp samples, the others 1) or foveated (a fixed pattern "
                 "of samples, dense at the --gaze point and sparse around it; each pixel "
                 "interpolates its 8 nearest samples) or reproject (with several views: the "
                 "centre view is path-traced and moved into the others by its depth; only "
                 "what it cannot see there, the holes, is path-traced; Leria et al. 6.3)")
      ->capture_default_str();
  cmd.add_option("--edge-spp", o.edge_spp, "Samples of edge pixels with --sampling adaptive")
      ->capture_default_str();
  cmd.add_option("--reference-spacing", o.reference_spacing,
                 "With --sampling reproject: path-trace every K-th view from the centre, across "
                 "and down, in full and reproject from all of them (ours; fewer holes in large "
                 "grids); 0: the centre view alone (Leria et al.)")
      ->capture_default_str();
  cmd.add_option("--gaze", o.gaze,
                 "Foveated: gaze point X,Y in normalised screen coordinates, 0,0 top left")
      ->capture_default_str();
  cmd.add_option("--gaze-path", o.gaze_path,
                 "Foveated: fixed, or orbit[:PERIOD] (the gaze circles --gaze at radius 0.25, "
                 "one turn per PERIOD frames, default 100)")
      ->capture_default_str();
  cmd.add_option("--fovea-spp", o.foveation.fovea_spp,
                 "Foveated: samples per pixel at the gaze point; density(r) = max(periphery, "
                 "fovea / (1 + (r/r0)^2))")
      ->capture_default_str();
  cmd.add_option("--fovea-radius", o.foveation.fovea_radius,
                 "Foveated: r0, where the density halves, as a fraction of the image height")
      ->capture_default_str();
  cmd.add_option("--periphery-spp", o.foveation.periphery_spp,
                 "Foveated: the density's floor far from the gaze, samples per pixel")
      ->capture_default_str();
  cmd.add_option("--perturb", o.perturb,
                 "FRAME:DEVICE:SPEED, repeatable: from FRAME on, DEVICE runs at emulated SPEED");
}

namespace {

// Writes each finished frame (PNG, EXR, quilt), prints its line, keeps its JSON record
// and, with --trace, its per-item measurements.
class RenderOutput : public FrameObserver {
 public:
  RenderOutput(const std::string& dir, bool exr, bool quiet, int columns, int frames,
               const Display& display, balance::TraceWriter* trace)
      : dir_(dir),
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
    if (stderr_is_tty()) fmt::print(stderr, "\r\033[K");
    const FrameRecord& rec = r->record;
    for (const auto& m : rec.messages) fmt::print(stderr, "multiray: warning: {}\n", m);
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
      fmt::print(
          "frame {:4d}  {:9.1f} ms  {:7.2f} Msamples/s  {:7.2f} Mrays/s  imbalance {:5.1f}%{}{}  "
          "-> {}.png\n",
          r->frame, rec.frame_ms, samples / rec.frame_ms / 1e3, rays / rec.frame_ms / 1e3,
          100.0 * rec.imbalance, adapted, holes, base + (images.size() > 1 ? "_quilt" : ""));
    json_.push_back(frame_to_json(rec));
    json_.back()["sampling_ms"] = r->sampling_ms;
    if (r->reprojection)
      json_.back()["reprojection"] =
          reprojection_to_json(r->reprojection->references, r->reprojection->hole_fraction());
    uint64_t hash = 0xcbf29ce484222325ull;
    for (const Framebuffer& img : images) hash = image_hash(img, hash);
    json_.back()["image_hash"] = fmt::format("{:016x}", hash);
    if (trace_) trace_->frame(r->stats);
  }

  const nlohmann::json& json() const { return json_; }

 private:
  std::string dir_;
  bool exr_, quiet_;
  int columns_, frames_;
  Display display_;
  balance::TraceWriter* trace_;
  nlohmann::json json_ = nlohmann::json::array();
};

// Makes `dir` ready for this run's outputs. A folder holding an earlier run's outputs
// (stats.json, frame_*) is refused, unless `overwrite`, when exactly those files are
// removed first, so the folder never mixes two runs. Other files are left alone.
void prepare_output_folder(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot create output folder '" + dir + "': " + ec.message());
  std::vector<fs::path> earlier;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name == "stats.json" || name.rfind("frame_", 0) == 0) earlier.push_back(e.path());
  }
  if (ec) throw InputError("cannot read output folder '" + dir + "': " + ec.message());
  if (earlier.empty()) return;
  if (!overwrite)
    throw InputError("--out '" + dir + "' holds an earlier run's outputs (" +
                     earlier.front().filename().string() +
                     ", ...); pass --overwrite to replace them, or choose another folder");
  for (const fs::path& p : earlier)
    if (!fs::remove(p, ec) || ec)
      throw InputError("cannot remove '" + p.string() + "': " + ec.message());
}

// On a terminal, a line shows how much of the frame has been handed to devices.
class ProgressLine {
 public:
  ProgressLine(const Session& session, int frames) {
    if (!stderr_is_tty()) return;
    thread_ = std::thread([this, &session, frames] {
      while (running_) {
        fmt::print(stderr, "\rrendering {} frame(s) ... {:3.0f}% of the current one", frames,
                   100.0 * session.progress());
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    });
  }
  ~ProgressLine() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace

Runner add_render_command(CLI::App& app, const std::vector<std::string>& command_line) {
  auto* cmd = app.add_subcommand("render", "Render frames to PNG (and EXR) files");
  auto o = std::make_shared<CommonOptions>();
  auto out_dir = std::make_shared<std::string>("out");
  auto exr = std::make_shared<bool>(false);
  auto balancer = std::make_shared<std::string>("hybrid");
  auto trace_path = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  add_common_options(*cmd, *o);
  auto overwrite = std::make_shared<bool>(false);
  cmd->add_option("--out", *out_dir,
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
  cmd->add_flag("-q,--quiet", *quiet, "No per-frame lines");
  return [=]() -> int {
    const std::string spec = apply_mapping(*balancer, o->mapping);
    Display display;
    display.exposure_ev = parse_exposure(*exposure);
    const bool volume_input = is_volume_input(o->scene_path, o->volume);
    display.tone = parse_tone(*tone, volume_input);
    Setup s = make_setup(*o, 1, [&] { prepare_output_folder(*out_dir, *overwrite); });
    if (s.cluster && !s.cluster->master()) return serve_as_worker(s);
    if (s.volume && s.volume->modes().size() > 1)
      throw InputError("--adapt: render takes one mode (bench compares several)");
    std::unique_ptr<Session> session = s.make_session({spec});
    for (const auto& n : s.notes) fmt::print(stderr, "multiray: note: {}\n", n);
    std::unique_ptr<TraceFile> trace;
    if (!trace_path->empty())
      trace = std::make_unique<TraceFile>(*trace_path, session->engine(0).balancer().spec(),
                                          s.devices);
    RenderOutput output(*out_dir, *exr, *quiet, s.views->rig().columns, o->frames, display,
                        trace ? &trace->writer() : nullptr);
    int done = 0;
    int interrupted = 0;
    std::string signal_name;
    {
      InterruptWatch watch(*session);
      ProgressLine progress(*session, o->frames);
      done = session->run(0, o->frames, output);
      interrupted = watch.signal();
      signal_name = watch.signal_name();
    }
    if (trace) trace->close();
    nlohmann::json settings = settings_to_json(*o, s, command_line);
    settings["balancer"] = spec;  // as asked; "balancer" below has every parameter
    settings["exposure_ev"] = display.exposure_ev;
    settings["tone"] = display.tone == ToneCurve::Filmic ? "filmic" : "clamp";
    settings["exr"] = *exr;
    nlohmann::json doc{{"scene", s.scene->name},
                       {"settings", settings},
                       {"devices", devices_to_json(s.devices)},
                       {"balancer", session->engine(0).balancer().spec()},
                       {"views", s.views->rig().view_count()},
                       {"frames_requested", o->frames},
                       {"frames", output.json()}};
    if (interrupted) doc["interrupted_by"] = signal_name;
    write_file_atomically(*out_dir + "/stats.json", doc.dump(1) + "\n");
    if (interrupted) {
      fmt::print(stderr,
                 "multiray: interrupted by {} after {} of {} frames; their images and "
                 "stats.json are complete\n",
                 signal_name, done, o->frames);
      return 128 + interrupted;
    }
    return 0;
  };
}

}  // namespace multiray::app
