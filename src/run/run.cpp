#include "run/run.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/core.h>

#include "balance/hierarchy.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/feature_buffers.h"
#include "device/device_factory.h"
#include "render/default_view.h"
#include "render/denoise.h"
#include "render/environment.h"
#include "render/kernel.h"
#include "render/volume_raycaster.h"
#include "run/ar_setup.h"
#include "run/catalog.h"
#include "run/lighting.h"
#include "run/run_fingerprint.h"
#include "scene/builders.h"
#include "scene/camera_check.h"
#include "scene/loaders.h"
#include "util/nearest.h"
#include "util/result_encoding.h"
#include "util/spec.h"
#include "volume/volume.h"

namespace multiray {
namespace {

// balance::top_level_spec, with a malformed spec reported against `option`.
std::string top_level_spec(const std::string& spec, const std::string& option) {
  try {
    return balance::top_level_spec(spec);
  } catch (const std::invalid_argument& e) {
    throw InputError(option + ": " + e.what());
  }
}

}  // namespace

std::vector<Device*> Run::device_ptrs() const {
  std::vector<Device*> out;
  for (const auto& d : devices) out.push_back(d.get());
  return out;
}

std::unique_ptr<Session> Run::make_session(const std::vector<std::string>& specs,
                                           const std::string& option) const {
  const size_t modes = volume ? volume->modes().size() : 1;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  for (const std::string& spec : specs) {
    // The master of a distributed run is the top of Harada's hierarchy (balance/hierarchy.h).
    const std::string chosen = resolve_balancer(spec, nullptr, option);
    const std::string lane = cluster ? top_level_spec(chosen, option) : chosen;
    for (size_t m = 0; m < modes; ++m)
      lanes.push_back(make_balancer_or_throw(lane, int(devices.size()), option));
  }
  auto session =
      std::make_unique<Session>(device_ptrs(), std::move(lanes), *views, path, settings);
  session->set_perturbations(perturbations);
  session->set_denoise(denoise);
  session->set_denoise_params(denoise_params);
  if (volume) {
    const int n = int(devices.size());
    session->set_advisors([&, modes, n](size_t lane) { return volume->advisor(lane % modes, n); });
    session->set_settings_schedule(
        [v = volume](int frame, RenderSettings& s) { v->apply(frame, s); });
  }
  return session;
}

std::vector<std::string> Run::lane_labels(const std::vector<std::string>& specs) const {
  std::vector<std::string> labels;
  const size_t modes = volume ? volume->modes().size() : 1;
  for (const std::string& spec : specs)
    for (size_t m = 0; m < modes; ++m)
      labels.push_back(modes > 1 ? spec + " adapt=" + balance::adapt_name(volume->modes()[m])
                                 : spec);
  return labels;
}

MemoryEstimate estimate_memory(const RunConfig& o, int views, int width, int height, int lanes) {
  MemoryEstimate m;
  std::error_code ec;
  if (!o.scene_path.empty()) {
    const auto size = std::filesystem::file_size(o.scene_path, ec);
    if (!ec) m.scene_bytes = 12.0 * double(size);
  }
  const double pixels = double(views) * width * height;
  const double per_pixel = sizeof(Vec3) * (2.0 * lanes + 2)        // results, engine, quilt
                           + (o.sampling == "adaptive" ? 32 : 0)   // G-buffer, maps
                           + (o.sampling == "reproject" ? 24 : 0)  // G-buffer, maps, depths
                           + (o.sampling == "foveated" ? 80 : 0)   // neighbours, weights
                           // --aov: 8 floats per pixel in each result and the engine's image
                           + (o.aovs.empty() && o.denoise == "none"
                                  ? 0
                                  : 32 * (2.0 * lanes + 1) + 12 * 6.0 * lanes);  // + denoiser
  m.frame_bytes = pixels * per_pixel;
  m.record_bytes = double(o.frames) * o.kept_bytes_per_frame;
  return m;
}

LoadOptions memory_guarded_load(double need, double limit,
                                const std::function<std::string(double images)>& parts) {
  LoadOptions load;
  load.parser_memory_limit = uint64_t(std::max(limit - need, 64.0 * (1 << 20)));
  // Textures and environment maps are charged from their headers, before they are decoded
  // (a 275 KB PNG may decode to 1 GB): what each keeps, and what decoding it takes besides.
  load.reserve_image = [need, limit, parts, kept = std::make_shared<double>(0)](
                           const std::string& what, uint64_t keep, uint64_t transient) {
    const double images = *kept + double(keep) + double(transient);
    if (need + images > limit)
      throw InputError(what + ": " + memory_refusal(need + images, parts(images), limit));
    *kept += double(keep);
  };
  return load;
}

namespace {
// Why `option` cannot have the run record feature buffers ("" when it can): other
// integrators, the shadow catcher's layer, samples not rendered per pixel (foveated,
// reprojected views).
std::string features_refused(const RunConfig& o, const RenderSettings& s, Sampling sampling,
                             const std::string& option) {
  if (s.kernel != "path")
    return option + " needs the path integrator's features, not --integrator " + s.kernel + "'s";
  if (s.catcher_axis >= 0) return option + " does not work with --ground yet";
  if (sampling == Sampling::Foveated || sampling == Sampling::Reprojected)
    return option + " works with uniform or adaptive sampling, not --sampling " + o.sampling;
  return "";
}

// Whether the run records feature buffers (--aov, RunConfig::aovs), refusing what cannot.
bool check_feature_buffers(const RunConfig& o, const RenderSettings& s, Sampling sampling) {
  if (o.aovs.empty()) return false;
  check_aov_names(o.aovs, "--aov");
  if (const std::string why = features_refused(o, s, sampling, "--aov"); !why.empty())
    throw InputError(why);
  return true;
}

// --denoise for this run (RunConfig::denoise): a method named where it cannot run is
// refused; auto is none there.
DenoiseMethod check_denoise(const RunConfig& o, const RenderSettings& s, Sampling sampling) {
  DenoiseChoice choice;
  if (!parse_denoise(o.denoise, choice)) {
    std::vector<std::string> names;
    for (const DenoiseMethodInfo& m : denoise_methods()) names.push_back(m.name);
    const std::string best = nearest_name(o.denoise, names);
    throw InputError("--denoise '" + o.denoise + "' must be none, atrous, svgf or auto" +
                     (best.empty() ? std::string() : " (did you mean " + best + "?)"));
  }
  const DenoiseMethod m = resolve_denoise(choice, {o.viewer, o.viewer, o.png_output, s.spp});
  if (m == DenoiseMethod::none) return m;
  if (const std::string why = features_refused(o, s, sampling, "--denoise"); !why.empty()) {
    if (choice == DenoiseChoice::automatic) return DenoiseMethod::none;
    throw InputError(why);
  }
  return m;
}

// The kernel the options ask for (by default the one the scene type needs), checked
// against the scene type before anything loads.
std::string check_kernel(const RunConfig& o, bool volume_input) {
  const std::string kernel =
      o.integrator.empty() ? (volume_input ? "volume" : "path") : o.integrator;
  const KernelEntry* e = find_cpu_kernel(kernel);
  if (!e) {
    std::string names;
    for (const KernelEntry& k : cpu_kernels()) names += (names.empty() ? "" : ", ") + k.name;
    throw InputError("--integrator '" + kernel + "' must be one of " + names);
  }
  if ((e->input == KernelInput::volume) != volume_input)
    throw InputError(volume_input ? "--integrator " + kernel +
                                        " renders triangles, and the scene is a volume (use "
                                        "--integrator volume)"
                                  : "--integrator volume needs a volume (.nhdr, .nrrd, or "
                                    "--raw), and the scene is a mesh");
  // The volume options are checked for meshes too: a mistyped value is an error, not
  // silently ignored because the scene happened to be a mesh.
  check_volume_options(o.volume);
  // Likewise --result-encoding without --distributed (it only matters to workers).
  try {
    parse_result_encoding(o.distributed.result_encoding);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--result-encoding ") + e.what());
  }
  if (volume_input) {
    if (o.sampling != "uniform")
      throw InputError("--sampling " + o.sampling + " is for meshes; volumes use uniform");
  }
  return kernel;
}
}  // namespace

namespace {
// --view-spacing auto: this fraction of the camera's distance to its target (the object
// it frames, or for an interior camera the point its orbit turns about). The
// stereographers' "1/30 rule" (a stereo base of a thirtieth of the distance to the
// subject) keeps the parallax across neighbouring views comfortable at any scene scale:
// 0.2 scene units sliced the bunny (0.15 across), while its default camera stands 0.3
// from it.
constexpr float kViewSpacingOfDistance = 1.0f / 30.0f;

// --up auto from what the loaded file says: a volume's superior axis (volume/volume.h),
// a mesh's declared up axis (Scene::file_up) with a note; else `up` stays (y, z).
void resolve_up_from_file(const Scene& scene, const std::string& path, bool volume_input, Vec3& up,
                          std::vector<std::string>& notes) {
  // Formats that carry no up axis but usually come from Z-up tools (3ds Max, Blender, CAD
  // and 3D printing): y is kept, and the way out is said once.
  static const char* const zup_formats[] = {".3ds", ".blend", ".stl", ".dxf", ".ifc"};
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (volume_input) {
    up = scene.volume->orientation.superior;
  } else if (dot(scene.file_up, scene.file_up) > 0.5f) {
    up = scene.file_up;
    const char* names[] = {"x", "y", "z"};
    const int axis = std::abs(up.x) > 0.5f ? 0 : std::abs(up.y) > 0.5f ? 1 : 2;
    notes.push_back(fmt::format("up axis {}{} from {} (--up auto; --up names another)",
                                up[axis] < 0 ? "-" : "+", names[axis], scene.file_up_from));
  } else if (std::find(std::begin(zup_formats), std::end(zup_formats), ext) !=
             std::end(zup_formats)) {
    notes.push_back(ext +
                    " files do not say which way is up and are often Z-up; y is "
                    "assumed: if the model lies on its side, pass --up z");
  }
}

// build_run() without the distributed part.
void fill_setup(Run& s, const RunConfig& o, int lanes, const std::function<void()>& before_load) {
  s.res = parse_resolution(o.resolution);
  if (o.spp < 0 || o.spp > 1 << 20) throw InputError("--spp must be in 0..1048576 (0: auto)");
  if (o.bounces < 0 || o.bounces > 1024) throw InputError("--bounces must be in 0..1024");
  check_frame_count(o.frames);
  if (!(o.clamp >= 0) || !std::isfinite(o.clamp))
    throw InputError("--clamp must be a finite number >= 0 (0: off)");
  int columns = 1, rows = 1;
  CameraRig rig;
  if (o.stereo > 0) {
    rig = CameraRig::stereo(o.stereo);
  } else {
    const auto x = o.views.find('x');
    if (x == std::string::npos) throw InputError("--views '" + o.views + "' must look like 3x3");
    const double k = to_number(o.views.substr(0, x), "--views"),
                 l = to_number(o.views.substr(x + 1), "--views");
    if (k < 1 || l < 1 || k > 64 || l > 64 || k != std::floor(k) || l != std::floor(l))
      throw InputError("--views '" + o.views + "': each count must be a whole number in 1..64");
    columns = int(k), rows = int(l);
    const double spacing =
        o.view_spacing == "auto" ? 0.0 : to_number(o.view_spacing, "--view-spacing");
    if (!(spacing >= 0) || !std::isfinite(spacing) || spacing > kMaxSceneCoordinate)
      throw InputError("--view-spacing must be auto or a finite number >= 0");
    rig = CameraRig::grid(columns, rows, float(spacing));  // auto: set with the camera
  }
  if (o.stereo < 0 || !std::isfinite(o.stereo))
    throw InputError("--stereo must be a finite number >= 0");
  if (int64_t(rig.view_count()) * s.res.width * s.res.height > (int64_t(1) << 30))
    throw InputError("--views x --res is more than 2^30 pixels per frame");
  const bool volume_input = is_volume_input(o.scene_path, o.volume);
  s.settings.kernel = check_kernel(o, volume_input);
  parse_ground(o.ground, s.settings);
  if (s.settings.catcher_axis >= 0)
    if (const std::string why = ground_conflict(o, s.settings.kernel, volume_input); !why.empty())
      throw InputError(why);
  if (o.ao_rays < 1 || o.ao_rays > 1024) throw InputError("--ao-rays must be in 1..1024");
  if (!(o.ao_distance >= 0) || !std::isfinite(o.ao_distance))
    throw InputError("--ao-distance must be a finite number >= 0 (0: 0.3 of the scene size)");
  s.settings.ao_rays = o.ao_rays;
  s.settings.ao_distance = o.ao_distance;
  if (o.sampling != "uniform" && o.sampling != "adaptive" && o.sampling != "foveated" &&
      o.sampling != "reproject")
    throw InputError("--sampling '" + o.sampling +
                     "' must be uniform, adaptive, foveated or reproject");
  if (o.edge_spp < 1 || o.edge_spp > 255) throw InputError("--edge-spp must be in 1..255");
  SamplingSetup sampling;
  sampling.mode = o.sampling == "adaptive"    ? Sampling::Adaptive
                  : o.sampling == "foveated"  ? Sampling::Foveated
                  : o.sampling == "reproject" ? Sampling::Reprojected
                                              : Sampling::Uniform;
  sampling.edge_spp = o.edge_spp;
  sampling.gaze = parse_gaze(o.gaze, o.gaze_path);
  if (!(o.foveation.fovea_spp > 0 && o.foveation.fovea_spp <= 64))
    throw InputError("--fovea-spp must be in (0, 64] samples per pixel");
  if (!(o.foveation.fovea_radius > 0) || !std::isfinite(o.foveation.fovea_radius))
    throw InputError("--fovea-radius must be a finite fraction of the image height > 0");
  if (!(o.foveation.periphery_spp >= 1.0f / 4096 &&
        o.foveation.periphery_spp <= o.foveation.fovea_spp))
    throw InputError("--periphery-spp must be in [1/4096, --fovea-spp] samples per pixel");
  s.settings.spp = o.spp > 0 ? o.spp : volume_input ? 1 : o.mesh_spp;
  s.settings.max_bounces = o.bounces;
  s.settings.sample_clamp = o.clamp;
  if (sampling.mode == Sampling::Reprojected) {
    if (rig.view_count() < 2)
      throw InputError("--sampling reproject needs several views (--views KxL or --stereo)");
    if (s.settings.spp > 255)
      throw InputError("--sampling reproject takes at most 255 samples per pixel (--spp)");
    sampling.reproject_spp = s.settings.spp;
    if (o.reference_spacing < 0 || o.reference_spacing > 64)
      throw InputError("--reference-spacing must be in 0..64 (0: the centre view alone)");
    sampling.reference_spacing = o.reference_spacing;
  }
  s.settings.seed = parse_seed(o.seed);
  s.can_record_features = features_refused(o, s.settings, sampling.mode, "").empty();
  s.settings.feature_buffers = check_feature_buffers(o, s.settings, sampling.mode);
  s.denoise = check_denoise(o, s.settings, sampling.mode);
  if (!parse_denoise_normal(o.denoise_normal, s.denoise_params))
    throw InputError("--denoise-normal '" + o.denoise_normal + "' must be turn or svgf");
  if (o.svgf_history != "filtered" && o.svgf_history != "accumulated")
    throw InputError("--svgf-history '" + o.svgf_history + "' must be filtered or accumulated");
  s.denoise_params.history_filtered = o.svgf_history == "filtered";
  s.settings.feature_buffers |= s.denoise != DenoiseMethod::none;
  std::optional<Camera> cli_camera;
  // --camera default: the framing default even where the file has a camera of its own.
  const bool framing_default = o.camera == "default";
  if (!o.camera.empty() && !framing_default) cli_camera = parse_camera(o.camera);
  s.up = parse_up(o.up, volume_input);
  // "threads=0" means every hardware thread; resolved here so the spec stays readable.
  std::string devices = s.cluster ? s.cluster->devices_of_this_rank(o.devices) : o.devices;
  // Each rank its own machine's. (What auto leaves out is said by `multiray devices` and
  // by the one-device summary that points there, not on every run.)
  if (devices == "auto") devices = auto_devices(offered_devices().devices).devices;
  const std::string all =
      "threads=" + std::to_string(std::max(1u, std::thread::hardware_concurrency()));
  for (size_t p; (p = devices.find("threads=0")) != std::string::npos &&
                 (p + 9 == devices.size() || devices[p + 9] == ':' || devices[p + 9] == ',');)
    devices.replace(p, 9, all);
  const auto specs = parse_device_specs(devices);  // check syntax before loading the scene
  for (const DeviceSpec& d : specs) {
    DeviceInfo info;
    info.spec = d.text;
    info.caps = backend_capabilities(d.type);
    const std::string why = unsupported_job(info, s.settings.kernel, o.sampling);
    if (!why.empty()) throw InputError("--devices: " + why);
    if (s.settings.catcher_axis >= 0 && !info.caps.shadow_catcher)
      throw InputError("--ground: the shadow catcher runs on " + shadow_catcher_backends() +
                       " devices only, not " + d.text);
  }
  if (!s.cluster) s.perturbations = parse_perturbations(o.perturb, int(specs.size()));

  const double limit = parse_memory_limit(o.max_memory);
  const MemoryEstimate need =
      estimate_memory(o, rig.view_count(), s.res.width, s.res.height, lanes);
  const auto parts = [need](double images) {
    return fmt::format("{:.1f} GB of frames, {:.1f} GB of scene", need.frame_bytes / 1e9,
                       need.scene_bytes / 1e9) +
           (need.record_bytes > 0
                ? fmt::format(", {:.1f} GB of per-frame records", need.record_bytes / 1e9)
                : "") +
           (images > 0 ? fmt::format(", {:.1f} GB of decoded images", images / 1e9) : "");
  };
  if (need.total() > limit) throw InputError(memory_refusal(need.total(), parts(0), limit));
  if (before_load) before_load();
  LoadOptions load = memory_guarded_load(need.total(), limit, parts);
  s.reserve_image = load.reserve_image;  // kept images are counted together
  load.allow_outside = o.allow_outside_paths;
  const bool sent = s.cluster && o.distributed.scene_from == "master";
  if (s.cluster) {  // what the master compares with each worker's (distributed/fingerprint.h)
    if (!sent) fingerprint_files(load, o.scene_path, s.fingerprint);
    fingerprint_options(o, volume_input, sent, s.fingerprint);
  }
  if (sent && !s.cluster->master()) {
    s.scene = std::make_unique<Scene>(s.cluster->receive_scene());
    if (o.up == "auto") s.up = s.scene->up;  // as the master resolved it
  } else {
    s.scene = std::make_unique<Scene>(
        o.scene_path.empty() ? make_cornell_box()
        : volume_input
            ? load_volume_scene(o.scene_path, o.volume, o.allow_outside_paths,
                                uint64_t(std::max(limit - need.frame_bytes, 0.0)), &s.notes)
            : load_scene(o.scene_path, load));
    if (o.up == "auto") resolve_up_from_file(*s.scene, o.scene_path, volume_input, s.up, s.notes);
    s.scene->up = s.up;
    apply_lighting({o.env, o.env_scale, o.sun}, volume_input, load, *s.scene, s.notes);
    if (s.settings.catcher_axis >= 0 && !EnvironmentLight(*s.scene).on())
      throw InputError(
          "--ground needs light from outside the scene (--env or --sun): the "
          "catcher's shadows are measured against it");
    if (sent) s.cluster->send_scene(*s.scene);
  }
  if (sampling.mode == Sampling::Foveated)
    sampling.pattern = std::make_shared<const FoveationPattern>(
        make_foveation_pattern(s.res.width, s.res.height, o.foveation));
  s.scenes = std::make_unique<SceneCache>(*s.scene);
  // The camera: --camera, the scene's own, or a default that frames it (for a mesh, the
  // view that sees the most front faces, or one inside an interior; render/default_view.h).
  const float aspect = float(s.res.width) / float(s.res.height);
  DefaultView chosen{Camera{}, cli_camera ? "--camera" : "scene"};
  if (cli_camera)
    chosen.camera = *cli_camera;
  else if (!s.scene->cameras.empty() && !framing_default) {
    chosen.camera = s.scene->cameras.front();
    const float outside = share_outside_frame(*s.scene, chosen.camera, aspect);
    if (outside > kCroppedShare)
      s.notes.push_back(fmt::format(
          "the file's own camera leaves {:.1f}% of the scene's vertices outside the frame (it "
          "crops the scene); --camera default frames all of it",
          100.0 * outside));
  } else if (volume_input)
    chosen = {default_volume_camera(*s.scene, aspect, s.up, s.scene->volume->orientation.anterior),
              "default"};
  else
    chosen = choose_default_view(s.scenes->embree(), aspect, s.up);
  s.camera_source = chosen.source;
  const Camera base = chosen.camera;
  s.camera = base;
  if (o.stereo <= 0 && o.view_spacing == "auto")
    rig.spacing = kViewSpacingOfDistance * length(base.target - base.eye);
  s.view_spacing = rig.view_count() > 1 ? rig.spacing : 0.0f;
  s.path = o.poses.empty() ? camera_path_option(o.camera_path, base)
                           : poses_path(o, s.res.width, s.res.height);
  if (volume_input) {
    s.volume = std::make_shared<VolumeRun>(*s.scenes, o.volume, s.scene->environment);
    s.volume->apply(0, s.settings);
    for (const std::string& n : s.volume->notes) s.notes.push_back(n);
    if (const InteractionSequence* seq = s.volume->sequence()) {
      if (o.camera_path != "fixed" && o.camera_path != "orbit")
        throw InputError("--sequence and --camera-path " + o.camera_path +
                         " both move the camera");
      s.path = sequence_path(*seq, base, o.frames);
    }
  }
  if (!s.cluster || !s.cluster->master() || o.distributed.master_renders)
    for (const DeviceSpec& d : specs) {
      s.devices.push_back(create_device(d, *s.scenes));
      for (const std::string& n : s.devices.back()->info().notes) s.notes.push_back(n);
    }
  // The G-buffer passes (adaptive edges, reprojection) run on the host, on the CPU
  // representation.
  const RenderScene* host =
      sampling.mode == Sampling::Adaptive || sampling.mode == Sampling::Reprojected
          ? &s.scenes->embree()
          : nullptr;
  s.views =
      std::make_unique<FrameViews>(rig, s.res.width, s.res.height, std::move(sampling), host);
}

// The master's checks of what cannot run distributed.
void check_distributed(const RunConfig& o) {
  if (o.sampling == "foveated")
    throw InputError(
        "--distributed: foveated sampling does not run on other ranks yet "
        "(uniform and adaptive do)");
  if (!o.volume.sequence.empty())
    throw InputError("--distributed: --sequence does not run on other ranks yet");
}
}  // namespace

int serve_as_worker(Run& s) { return s.cluster->serve(s.device_ptrs(), s.settings); }

void check_frame_count(int frames) {
  if (frames < 1 || frames > 1000000) throw InputError("--frames must be in 1..1000000");
}

CameraPath camera_path_option(const std::string& cp, const Camera& base) {
  if (cp == "fixed") return CameraPath::fixed(base);
  if (cp == "orbit" || cp.rfind("orbit:", 0) == 0) {
    const double period =
        cp == "orbit" ? 100.0 : to_number(cp.substr(6), "--camera-path orbit period");
    if (!(period >= 1e-3 && period <= 1e9))
      throw InputError("--camera-path: the orbit period must be in [0.001, 1e9] frames");
    return CameraPath::orbit(base, float(period));
  }
  return CameraPath::from_json_file(cp);
}

Run build_run(const RunConfig& o, int lanes, const std::function<void()>& before_load) {
  Run s;
  s.mapping = o.mapping;
  if (!o.distributed.enabled) {
    fill_setup(s, o, lanes, before_load);
    s.auto_inputs = gather_auto_inputs(s, o);
    return s;
  }
  s.cluster = std::make_shared<Cluster>(o.distributed);
  if (!s.cluster->master()) {
    // A worker that cannot start tells the master and ends with 0: the master reports it
    // ("rank R: ...") and ends the run with its own non-zero code. Ending non-zero here
    // let mpiexec abort the job before the master had printed why (seen in CI's tests).
    try {
      check_distributed(o);
      fill_setup(s, o, lanes, {});
    } catch (const std::exception& e) {
      s.cluster->say_cannot_start(e.what());
      throw QuietExit{0};
    }
    s.cluster->say_hello(s.devices, s.fingerprint);
    return s;
  }
  check_distributed(o);
  fill_setup(s, o, lanes, before_load);
  std::vector<std::unique_ptr<Device>> all = s.cluster->connect_workers(s.fingerprint);
  for (auto& d : s.devices) all.push_back(std::move(d));
  s.devices = std::move(all);
  s.perturbations = parse_perturbations(o.perturb, int(s.devices.size()));
  s.notes.push_back(
      fmt::format("distributed over {} ranks: the master{} and {} worker(s); link: {}",
                  s.cluster->size(), o.distributed.master_renders ? " (rendering too)" : "",
                  s.cluster->size() - 1, s.cluster->link().describe()));
  for (const auto& d : s.devices) {
    const std::string why = unsupported_job(d->info(), s.settings.kernel, o.sampling);
    if (!why.empty()) throw InputError("--distributed: " + why);
  }
  s.auto_inputs = gather_auto_inputs(s, o);
  return s;
}

}  // namespace multiray
