#include "app/options.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/core.h>

#include "app/lighting_options.h"
#include "app/stats_json.h"
#include "balance/spec.h"
#include "core/clock.h"
#include "core/error.h"
#include "device/device_factory.h"
#include "render/default_view.h"
#include "render/kernel.h"
#include "render/volume_raycaster.h"
#include "scene/builders.h"
#include "scene/camera_check.h"
#include "scene/loaders.h"

namespace multiray::app {

// Strict numeric parsing: the whole token must be a finite number.
double to_number(const std::string& tok, const std::string& what) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(tok, &used);
  } catch (...) {
    used = 0;
  }
  if (tok.empty() || used != tok.size() || !std::isfinite(v))
    throw InputError(what + ": '" + tok + "' is not a number");
  return v;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.push_back("");
  return out;
}

uint64_t parse_seed(const std::string& text) {
  // Digits only: "-1" must not wrap around to 2^64 - 1, nor "1e3" become 1.
  bool digits = !text.empty() && text.size() <= 20;
  for (char c : text) digits &= c >= '0' && c <= '9';
  errno = 0;
  const unsigned long long v = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
  if (!digits || errno == ERANGE)
    throw InputError("--seed '" + text + "' must be a whole number in 0..18446744073709551615");
  return uint64_t(v);
}

Resolution parse_resolution(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw InputError("--res '" + text + "' must look like 640x360");
  const double w = to_number(text.substr(0, x), "--res width");
  const double h = to_number(text.substr(x + 1), "--res height");
  constexpr int kMax = 16384;
  if (w < 1 || h < 1 || w != std::floor(w) || h != std::floor(h))
    throw InputError("--res '" + text + "': width and height must be whole numbers of at least 1");
  if (w > kMax || h > kMax)
    throw InputError("--res '" + text + "': at most " + std::to_string(kMax) + " pixels per side");
  return {int(w), int(h)};
}

Camera parse_camera(const std::string& text) {
  const auto parts = split(text, ',');
  if (parts.size() != 10)
    throw InputError("--camera needs 10 numbers: eye x,y,z, target x,y,z, up x,y,z, fov (got " +
                     std::to_string(parts.size()) + ")");
  float v[10];
  for (int i = 0; i < 10; ++i) v[i] = float(to_number(parts[size_t(i)], "--camera"));
  Camera c{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
  const std::string problem = camera_problem(c);  // checked as floats, as rendered
  if (!problem.empty()) throw InputError("--camera: " + problem);
  return c;
}

Vec3 parse_up(const std::string& text, bool volume) {
  Vec3 up = volume ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
  if (text != "auto" && !up_axis_vector(text, up))
    throw InputError("--up '" + text + "' must be auto, x, y or z, optionally signed (+z, -y)");
  return up;
}

float parse_exposure(double ev) {
  if (!(ev >= -20 && ev <= 20)) throw InputError("--exposure must be in [-20, 20] stops");
  return float(ev);
}

ToneCurve parse_tone(const std::string& text, bool volume) {
  if (text == "filmic") return ToneCurve::Filmic;
  if (text == "clamp") return ToneCurve::Clamp;
  if (text == "auto") return volume ? ToneCurve::Clamp : ToneCurve::Filmic;
  throw InputError("--tone '" + text + "' must be filmic, clamp or auto");
}

GazePath parse_gaze(const std::string& gaze, const std::string& path) {
  GazePath g;
  const auto parts = split(gaze, ',');
  if (parts.size() != 2) throw InputError("--gaze '" + gaze + "' must look like 0.5,0.5");
  const double x = to_number(parts[0], "--gaze x"), y = to_number(parts[1], "--gaze y");
  if (x < 0 || x > 1 || y < 0 || y > 1)
    throw InputError("--gaze '" + gaze + "': X and Y are normalised, each must be in [0, 1]");
  g.center = Vec2{float(x), float(y)};
  if (path == "orbit" || path.rfind("orbit:", 0) == 0) {
    g.radius = 0.25f;
    if (path != "orbit") {
      const double period = to_number(path.substr(6), "--gaze-path orbit period");
      if (!(period >= 1e-3 && period <= 1e9))
        throw InputError("--gaze-path: the orbit period must be in [0.001, 1e9] frames");
      g.period = float(period);
    }
  } else if (path != "fixed") {
    throw InputError("--gaze-path '" + path + "' must be fixed, orbit or orbit:PERIOD");
  }
  return g;
}

std::vector<Perturbation> parse_perturbations(const std::vector<std::string>& items,
                                              int device_count) {
  std::vector<Perturbation> out;
  for (const std::string& it : items) {
    const auto p = split(it, ':');
    if (p.size() != 3)
      throw InputError("--perturb '" + it + "' must look like FRAME:DEVICE:SPEED, e.g. 50:0:0.5");
    const double f = to_number(p[0], "--perturb frame"), d = to_number(p[1], "--perturb device"),
                 s = to_number(p[2], "--perturb speed");
    if (f < 0 || f != std::floor(f))
      throw InputError("--perturb '" + it + "': frame must be a whole number >= 0");
    if (d < 0 || d != std::floor(d) || d >= device_count)
      throw InputError("--perturb '" + it + "': device must be 0.." +
                       std::to_string(device_count - 1));
    if (f > 1e9) throw InputError("--perturb '" + it + "': frame must be at most 1e9");
    if (!(s >= kMinEmulatedSpeed && s <= 1))
      throw InputError("--perturb '" + it + "': speed must be in [0.01, 1] (emulated)");
    out.push_back({int(f), int(d), s});
  }
  return out;
}

std::vector<Device*> Setup::device_ptrs() const {
  std::vector<Device*> out;
  for (const auto& d : devices) out.push_back(d.get());
  return out;
}

std::unique_ptr<Session> Setup::make_session(const std::vector<std::string>& specs,
                                             const std::string& option) const {
  const size_t modes = volume ? volume->modes().size() : 1;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  for (const std::string& spec : specs)
    for (size_t m = 0; m < modes; ++m)
      lanes.push_back(make_balancer_or_throw(spec, int(devices.size()), option));
  auto session =
      std::make_unique<Session>(device_ptrs(), std::move(lanes), *views, path, settings);
  session->set_perturbations(perturbations);
  if (volume) {
    const int n = int(devices.size());
    session->set_advisors([&, modes, n](size_t lane) { return volume->advisor(lane % modes, n); });
    session->set_settings_schedule(
        [v = volume](int frame, RenderSettings& s) { v->apply(frame, s); });
  }
  return session;
}

std::vector<std::string> Setup::lane_labels(const std::vector<std::string>& specs) const {
  std::vector<std::string> labels;
  const size_t modes = volume ? volume->modes().size() : 1;
  for (const std::string& spec : specs)
    for (size_t m = 0; m < modes; ++m)
      labels.push_back(modes > 1 ? spec + " adapt=" + balance::adapt_name(volume->modes()[m])
                                 : spec);
  return labels;
}

std::string apply_mapping(const std::string& text, const std::string& mapping,
                          const std::string& option) {
  if (mapping.empty()) return text;
  if (mapping != "strips" && mapping != "views")
    throw InputError("--mapping '" + mapping + "' must be strips or views");
  const balance::Spec spec = [&] {
    try {
      return balance::Spec(text);
    } catch (const std::invalid_argument& e) {
      throw InputError(option + ": " + e.what());
    }
  }();
  const std::string& name = spec.name();
  if (name == "uniform" || name == "static" || name == "dlb")
    return spec.has("layout") ? text : text + ":layout=" + mapping;
  if (mapping == "views")
    throw InputError("--mapping views works with the uniform, static and dlb balancers, not '" +
                     name + "'");
  return text;  // queue, semi-static and hybrid lay out work their own way
}

double parse_memory_limit(const std::string& text) {
  if (text == "auto")
    return 0.5 * double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  double unit = 1;
  std::string digits = text;
  if (!digits.empty() && std::string("KMGT").find(digits.back()) != std::string::npos) {
    unit = std::pow(1024.0, double(std::string("KMGT").find(digits.back()) + 1));
    digits.pop_back();
  }
  const double v = to_number(digits, "--max-memory") * unit;
  if (!(v >= 1 << 20 && v <= 1e15))
    throw InputError("--max-memory '" + text + "' must be auto or a size from 1M to 1e15 bytes");
  return v;
}

MemoryEstimate estimate_memory(const CommonOptions& o, int views, int width, int height,
                               int lanes) {
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
                           + (o.sampling == "foveated" ? 80 : 0);  // neighbours, weights
  m.frame_bytes = pixels * per_pixel;
  return m;
}

namespace {
// The kernel the options ask for (by default the one the scene type needs), checked
// against the scene type before anything loads.
std::string check_kernel(const CommonOptions& o, bool volume_input) {
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
  if (volume_input) {
    check_volume_options(o.volume);
    if (o.sampling != "uniform")
      throw InputError("--sampling " + o.sampling + " is for meshes; volumes use uniform");
  }
  return kernel;
}
}  // namespace

namespace {
// make_setup() without the distributed part.
void fill_setup(Setup& s, const CommonOptions& o, int lanes,
                const std::function<void()>& before_load) {
  s.res = parse_resolution(o.resolution);
  if (o.spp < 0 || o.spp > 1 << 20) throw InputError("--spp must be in 0..1048576 (0: auto)");
  if (o.bounces < 0 || o.bounces > 1024) throw InputError("--bounces must be in 0..1024");
  if (o.frames < 1 || o.frames > 1000000) throw InputError("--frames must be in 1..1000000");
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
    if (!(o.view_spacing >= 0) || !std::isfinite(o.view_spacing))
      throw InputError("--view-spacing must be a finite number >= 0");
    rig = CameraRig::grid(columns, rows, o.view_spacing);
  }
  if (o.stereo < 0 || !std::isfinite(o.stereo))
    throw InputError("--stereo must be a finite number >= 0");
  if (int64_t(rig.view_count()) * s.res.width * s.res.height > (int64_t(1) << 30))
    throw InputError("--views x --res is more than 2^30 pixels per frame");
  const bool volume_input = is_volume_input(o.scene_path, o.volume);
  s.settings.kernel = check_kernel(o, volume_input);
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
  std::optional<Camera> cli_camera;
  if (!o.camera.empty()) cli_camera = parse_camera(o.camera);
  s.up = parse_up(o.up, volume_input);
  // "threads=0" means every hardware thread; resolved here so the spec stays readable.
  std::string devices = s.cluster ? s.cluster->devices_of_this_rank(o.devices) : o.devices;
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
  }
  if (!s.cluster) s.perturbations = parse_perturbations(o.perturb, int(specs.size()));

  const double limit = parse_memory_limit(o.max_memory);
  const MemoryEstimate need =
      estimate_memory(o, rig.view_count(), s.res.width, s.res.height, lanes);
  if (need.total() > limit)
    throw InputError(fmt::format(
        "this run needs about {:.1f} GB ({:.1f} GB of frames, {:.1f} GB of scene), more than "
        "the {:.1f} GB allowed (--max-memory; default: half of physical memory)",
        need.total() / 1e9, need.frame_bytes / 1e9, need.scene_bytes / 1e9, limit / 1e9));
  if (before_load) before_load();
  LoadOptions load;
  load.allow_outside = o.allow_outside_paths;
  const bool sent = s.cluster && o.distributed.scene_from == "master";
  if (sent && !s.cluster->master()) {
    s.scene = std::make_unique<Scene>(s.cluster->receive_scene());
  } else {
    s.scene = std::make_unique<Scene>(
        o.scene_path.empty() ? make_cornell_box()
        : volume_input       ? load_volume_scene(o.scene_path, o.volume, o.allow_outside_paths,
                                                 uint64_t(std::max(limit - need.frame_bytes, 0.0)))
                             : load_scene(o.scene_path, load));
    s.scene->up = s.up;
    apply_lighting({o.env, o.env_scale, o.sun}, volume_input, load, *s.scene, s.notes);
    if (sent) s.cluster->send_scene(*s.scene);
  }
  if (sampling.mode == Sampling::Foveated)
    sampling.pattern = std::make_shared<const FoveationPattern>(
        make_foveation_pattern(s.res.width, s.res.height, o.foveation));
  s.scenes = std::make_unique<SceneCache>(*s.scene);
  // The camera: --camera, the scene's own, or a default that frames it (for a mesh, the
  // view that sees the most front faces; render/default_view.h).
  const float aspect = float(s.res.width) / float(s.res.height);
  s.camera_source = cli_camera ? "--camera" : !s.scene->cameras.empty() ? "scene" : "default";
  const Camera base = cli_camera                  ? *cli_camera
                      : !s.scene->cameras.empty() ? s.scene->cameras.front()
                      : volume_input              ? s.scene->default_camera(aspect, s.up)
                                     : choose_default_camera(s.scenes->embree(), aspect, s.up);
  s.camera = base;
  const std::string& cp = o.camera_path;
  if (cp == "fixed") {
    s.path = CameraPath::fixed(base);
  } else if (cp == "orbit" || cp.rfind("orbit:", 0) == 0) {
    const double period =
        cp == "orbit" ? 100.0 : to_number(cp.substr(6), "--camera-path orbit period");
    if (!(period >= 1e-3 && period <= 1e9))
      throw InputError("--camera-path: the orbit period must be in [0.001, 1e9] frames");
    s.path = CameraPath::orbit(base, float(period));
  } else {
    s.path = CameraPath::from_json_file(cp);
  }
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
    for (const DeviceSpec& d : specs) s.devices.push_back(create_device(d, *s.scenes));
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
void check_distributed(const CommonOptions& o) {
  if (o.sampling == "foveated")
    throw InputError(
        "--distributed: foveated sampling does not run on other ranks yet "
        "(uniform and adaptive do)");
  if (!o.volume.sequence.empty())
    throw InputError("--distributed: --sequence does not run on other ranks yet");
}
}  // namespace

Setup make_setup(const CommonOptions& o, int lanes, const std::function<void()>& before_load) {
  Setup s;
  if (!o.distributed.enabled) {
    fill_setup(s, o, lanes, before_load);
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
    s.cluster->say_hello(s.devices);
    return s;
  }
  check_distributed(o);
  fill_setup(s, o, lanes, before_load);
  std::vector<std::unique_ptr<Device>> all = s.cluster->connect_workers();
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
  return s;
}

}  // namespace multiray::app
