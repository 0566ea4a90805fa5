#include "app/options.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "app/stats_json.h"
#include "balance/spec.h"
#include "core/clock.h"
#include "core/error.h"
#include "device/device_factory.h"
#include "render/kernel.h"
#include "scene/builders.h"
#include "scene/loaders.h"

namespace multiray::app {

namespace {

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

bool has_emitter(const Scene& scene) {
  for (const Material& m : scene.materials)
    if (max_component(m.emission) > 0) return true;
  return false;
}

}  // namespace

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
  if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180))
    throw InputError("--camera: fov must be in (0, 180) degrees");
  if (length(c.target - c.eye) == 0)
    throw InputError("--camera: eye and target are the same point");
  if (length(cross(c.target - c.eye, c.up)) == 0)
    throw InputError("--camera: up is parallel to the viewing direction");
  return c;
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
      if (!(period > 0)) throw InputError("--gaze-path: the orbit period must be > 0 frames");
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
    if (!(s > 0 && s <= 1))
      throw InputError("--perturb '" + it + "': speed must be in (0, 1] (emulated)");
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
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  for (const std::string& spec : specs)
    lanes.push_back(make_balancer_or_throw(spec, int(devices.size()), option));
  auto session =
      std::make_unique<Session>(device_ptrs(), std::move(lanes), *views, path, settings);
  session->set_perturbations(perturbations);
  return session;
}

std::string apply_mapping(const std::string& text, const std::string& mapping) {
  if (mapping.empty()) return text;
  if (mapping != "strips" && mapping != "views")
    throw InputError("--mapping '" + mapping + "' must be strips or views");
  const balance::Spec spec = [&] {
    try {
      return balance::Spec(text);
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("--balancer: ") + e.what());
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

Setup make_setup(const CommonOptions& o) {
  Setup s;
  s.res = parse_resolution(o.resolution);
  if (o.spp < 1 || o.spp > 1 << 20) throw InputError("--spp must be in 1..1048576");
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
  if (!find_cpu_kernel(o.integrator)) {
    std::string names;
    for (const KernelEntry& e : cpu_kernels()) names += (names.empty() ? "" : ", ") + e.name;
    throw InputError("--integrator '" + o.integrator + "' must be one of " + names);
  }
  s.settings.kernel = o.integrator;
  if (o.ao_rays < 1 || o.ao_rays > 1024) throw InputError("--ao-rays must be in 1..1024");
  if (!(o.ao_distance >= 0) || !std::isfinite(o.ao_distance))
    throw InputError("--ao-distance must be a finite number >= 0 (0: 0.3 of the scene size)");
  s.settings.ao_rays = o.ao_rays;
  s.settings.ao_distance = o.ao_distance;
  if (o.sampling != "uniform" && o.sampling != "adaptive" && o.sampling != "foveated")
    throw InputError("--sampling '" + o.sampling + "' must be uniform, adaptive or foveated");
  if (o.edge_spp < 1 || o.edge_spp > 255) throw InputError("--edge-spp must be in 1..255");
  SamplingSetup sampling;
  sampling.mode = o.sampling == "adaptive"   ? Sampling::Adaptive
                  : o.sampling == "foveated" ? Sampling::Foveated
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
  s.settings.spp = o.spp;
  s.settings.max_bounces = o.bounces;
  s.settings.seed = o.seed;
  std::optional<Camera> cli_camera;
  if (!o.camera.empty()) cli_camera = parse_camera(o.camera);
  // "threads=0" means every hardware thread; resolved here so the spec stays readable.
  std::string devices = o.devices;
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
  s.perturbations = parse_perturbations(o.perturb, int(specs.size()));

  s.scene = std::make_unique<Scene>(o.scene_path.empty() ? make_cornell_box()
                                                         : load_scene(o.scene_path));
  const float aspect = float(s.res.width) / float(s.res.height);
  const Camera base = cli_camera                  ? *cli_camera
                      : !s.scene->cameras.empty() ? s.scene->cameras.front()
                                                  : s.scene->default_camera(aspect);
  const std::string& cp = o.camera_path;
  if (cp == "fixed") {
    s.path = CameraPath::fixed(base);
  } else if (cp == "orbit" || cp.rfind("orbit:", 0) == 0) {
    const double period =
        cp == "orbit" ? 100.0 : to_number(cp.substr(6), "--camera-path orbit period");
    if (!(period > 0)) throw InputError("--camera-path: the orbit period must be > 0 frames");
    s.path = CameraPath::orbit(base, float(period));
  } else {
    s.path = CameraPath::from_json_file(cp);
  }
  if (o.env != "auto") {
    const auto parts = split(o.env, ',');
    if (parts.size() != 1 && parts.size() != 3)
      throw InputError("--env '" + o.env + "' must be one number or R,G,B");
    for (int c = 0; c < 3; ++c) {
      const double v = to_number(parts[parts.size() == 1 ? 0 : size_t(c)], "--env");
      if (v < 0) throw InputError("--env must not be negative");
      s.scene->environment[c] = float(v);
    }
  } else if (max_component(s.scene->environment) <= 0 && !has_emitter(*s.scene)) {
    s.scene->environment = Vec3(1.0f);
    s.notes.push_back("the scene has no lights; using a white sky (radiance 1), see --env");
  }
  if (sampling.mode == Sampling::Foveated)
    sampling.pattern = std::make_shared<const FoveationPattern>(
        make_foveation_pattern(s.res.width, s.res.height, o.foveation));
  s.scenes = std::make_unique<SceneCache>(*s.scene);
  for (const DeviceSpec& d : specs) s.devices.push_back(create_device(d, *s.scenes));
  // The adaptive edge pass runs on the host, on the CPU representation.
  const RenderScene* host = sampling.mode == Sampling::Adaptive ? &s.scenes->embree() : nullptr;
  s.views =
      std::make_unique<FrameViews>(rig, s.res.width, s.res.height, std::move(sampling), host);
  return s;
}

}  // namespace multiray::app
