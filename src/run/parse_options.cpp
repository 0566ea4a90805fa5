#include "run/parse_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <fmt/core.h>

#include "core/error.h"
#include "run/run.h"
#include "scene/camera_check.h"
#include "util/parse.h"
#include "util/spec.h"

namespace multiray {

double to_number(const std::string& tok, const std::string& what) {
  const std::optional<double> v = parse_number(tok);
  if (!v) throw InputError(what + ": '" + tok + "' is not a number");
  return *v;
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

std::string apply_mapping(const std::string& text, const std::string& mapping,
                          const std::string& option) {
  if (mapping.empty()) return text;
  if (mapping != "strips" && mapping != "views")
    throw InputError("--mapping '" + mapping + "' must be strips or views");
  const Spec spec = [&] {
    try {
      return Spec(text);
    } catch (const std::invalid_argument& e) {
      throw InputError(option + ": " + e.what());
    }
  }();
  const std::string& name = spec.name();
  if (name == "auto") return text;  // Run::resolve_balancer maps what auto picks
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
  const double v = parse_size(text).value_or(0);
  if (!(v >= 1 << 20 && v <= 1e15))
    throw InputError("--max-memory '" + text + "' must be auto or a size from 1M to 1e15 bytes");
  return v;
}

std::string memory_refusal(double need, const std::string& parts, double limit) {
  return fmt::format(
      "this run needs about {:.1f} GB ({}), more than the {:.1f} GB allowed (--max-memory; "
      "default: half of physical memory)",
      need / 1e9, parts, limit / 1e9);
}

std::unique_ptr<balance::Balancer> make_balancer_or_throw(const std::string& spec, int devices,
                                                          const std::string& option) {
  try {
    return balance::make_balancer(spec, devices);
  } catch (const std::invalid_argument& e) {
    throw InputError(option + ": " + e.what());
  }
}

}  // namespace multiray
