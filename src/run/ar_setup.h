// The augmented-reality part of a run (docs/ar.md): --ground's shadow catcher checked
// against everything else the run asks for, and --poses as the camera path.
#pragma once

#include <string>

#include "render/render_settings.h"
#include "run/run_config.h"
#include "scene/camera_path.h"

namespace multiray {

struct Resolution;

// Parses --ground "AXIS=HEIGHT[,albedo=A]" (AXIS x, y or z; HEIGHT finite; A in [0, 1])
// into `settings`; empty: no catcher. InputError naming --ground otherwise.
void parse_ground(const std::string& text, RenderSettings& settings);

// What cannot take a shadow catcher, as one line naming the option (empty: fine): volumes,
// other integrators, foveated or reprojected sampling, light-field views, MPI. Called
// before the scene loads.
std::string ground_conflict(const RunConfig& o, const std::string& kernel, bool volume_input);

// --poses as a camera path, checked against --res (the aspect ratios must agree within
// 1%), --camera-path (which it replaces) and --frames (at most one frame a pose: frames
// past the last would silently repeat it). InputError otherwise.
CameraPath poses_path(const RunConfig& o, int width, int height);

// How many frames --poses holds (for --frames' default).
int pose_count(const std::string& path);

}  // namespace multiray
