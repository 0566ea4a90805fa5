#include "run/lighting.h"

#include <cmath>
#include <memory>

#include "core/error.h"
#include "run/parse_options.h"

#include <fmt/format.h>

namespace multiray {

namespace {

// Whether some material emits by its factor alone. Emission through a texture does not
// count: such files (DamagedHelmet) mean glowing details, not a light for the scene.
bool has_light(const Scene& scene) {
  for (const Material& m : scene.materials)
    if (max_component(m.emission) > 0 && m.emission_texture < 0) return true;
  return false;
}

bool has_textured_emission(const Scene& scene) {
  for (const Material& m : scene.materials)
    if (max_component(m.emission) > 0 && m.emission_texture >= 0) return true;
  return false;
}

bool is_map_file(const std::string& text) {
  auto ends = [&](const char* ext) {
    const size_t n = std::char_traits<char>::length(ext);
    if (text.size() < n) return false;
    for (size_t i = 0; i < n; ++i)
      if (std::tolower(static_cast<unsigned char>(text[text.size() - n + i])) != ext[i])
        return false;
    return true;
  };
  return ends(".hdr") || ends(".exr");
}

Vec3 parse_colour(const std::string& text) {
  const auto parts = split(text, ',');
  if (parts.size() != 1 && parts.size() != 3)
    throw InputError("--env '" + text + "' must be auto, one number, R,G,B or a .hdr/.exr file");
  Vec3 c;
  for (int k = 0; k < 3; ++k) {
    const double v = to_number(parts[parts.size() == 1 ? 0 : size_t(k)], "--env");
    if (!(v >= 0 && v <= 1e9)) throw InputError("--env must be in [0, 1e9]");
    c[k] = float(v);
  }
  return c;
}

}  // namespace

Sun parse_sun(const std::string& text, Vec3 up) {
  Sun sun;
  if (text == "off" || text == "auto") return sun;
  const auto parts = split(text, ',');
  if (parts.size() < 2 || parts.size() > 4)
    throw InputError("--sun '" + text +
                     "' must be auto, off or AZIMUTH,ELEVATION[,IRRADIANCE[,DIAMETER]] (degrees, "
                     "W/m^2 in scene units, degrees)");
  const double az = to_number(parts[0], "--sun azimuth");
  const double el = to_number(parts[1], "--sun elevation");
  const double e = parts.size() > 2 ? to_number(parts[2], "--sun irradiance") : 3.0;
  const double diameter = parts.size() > 3 ? to_number(parts[3], "--sun diameter") : 0.53;
  if (!(az >= -360 && az <= 360) || !(el >= -90 && el <= 90))
    throw InputError("--sun: azimuth must be in [-360, 360] and elevation in [-90, 90] degrees");
  if (!(e > 0 && e <= 1e9)) throw InputError("--sun: irradiance must be in (0, 1e9]");
  if (!(diameter >= 0.01 && diameter <= 90))
    throw InputError("--sun: the diameter must be in [0.01, 90] degrees");
  sun.direction = view_direction(up, float(az), float(el));
  sun.half_angle_rad = float(0.5 * diameter * kPi / 180.0);
  // Irradiance at normal incidence from a disc of constant radiance L: E = L pi sin^2(a).
  const double s = std::sin(double(sun.half_angle_rad));
  sun.radiance = Vec3(float(e / (kPi * s * s)));
  return sun;
}

void apply_lighting(const LightingOptions& o, bool volume, const LoadOptions& load, Scene& scene,
                    std::vector<std::string>& notes) {
  if (!(o.env_scale >= 0 && o.env_scale <= 1e9))
    throw InputError("--env-scale must be in [0, 1e9]");
  scene.sun = parse_sun(o.sun, scene.up);
  if (is_map_file(o.env)) {
    scene.environment_map = std::make_shared<EnvironmentMap>(load_environment_map(o.env, load));
    scene.environment_map_scale = float(o.env_scale);
    scene.environment = Vec3(0.0f);
  } else if (o.env != "auto") {
    scene.environment = parse_colour(o.env);
  } else if (!volume && max_component(scene.environment) <= 0 && !has_light(scene)) {
    // Daylight: a uniform sky alone shows a light model as a flat silhouette against an
    // equally bright background; the sun gives it shading and shadows.
    // With the sun, the sky is dimmer (about a third of the sun's irradiance, as on a
    // clear day), so the lit side of a light model stands out from the background.
    const bool sun = o.sun == "auto";
    const float sky = sun ? kDaylightSky : 1.0f;
    scene.environment = Vec3(sky);
    std::string what = "a white sky (radiance " + fmt::format("{:g}", sky) + ")";
    if (sun) {
      scene.sun = parse_sun(kDaylightSun, scene.up);
      what += std::string(" and a sun (--sun ") + kDaylightSun + ")";
    }
    notes.push_back(std::string(has_textured_emission(scene)
                                    ? "the scene's only lights are emissive textures"
                                    : "the scene has no lights") +
                    "; adding " + what + ", see --env and --sun");
  }
}

}  // namespace multiray
