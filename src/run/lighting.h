// --env, --env-scale and --sun: the light from outside the scene.
#pragma once

#include <string>
#include <vector>

#include "scene/loaders.h"
#include "scene/scene.h"

namespace multiray {

struct LightingOptions {
  std::string env = "auto";  // auto | V | R,G,B | FILE.hdr | FILE.exr
  double env_scale = 1.0;    // multiplies an environment map
  std::string sun = "auto";  // auto | off | AZ,EL[,IRRADIANCE[,DIAMETER]]
};

// The sun of default daylight (--env auto on a scene without lights, --sun auto): from the
// left of the default camera and well above the horizon, with the irradiance of ~1 sky.
constexpr const char* kDaylightSun = "-40,55,3";
constexpr float kDaylightSky = 0.3f;  // the white sky's radiance with that sun

// Sets the scene's environment and sun from `o` (scene.up must already be the run's up
// axis). With env = auto and no light at all, daylight is added (a white sky, and with
// sun = auto the kDaylightSun) and `notes` says so. sun = auto is off otherwise.
// Throws InputError with a one-line message for a bad value or an unreadable map.
void apply_lighting(const LightingOptions& o, bool volume, const LoadOptions& load, Scene& scene,
                    std::vector<std::string>& notes);

// The sun of --sun's text for up axis `up` (off: radiance 0).
Sun parse_sun(const std::string& text, Vec3 up);

}  // namespace multiray
