// Whether a camera can produce a valid image: the one check used for --camera, keyframe
// files, orbits and cameras set while a session runs, so that every ray a kernel traces is
// finite by construction.
#pragma once

#include <string>

#include "scene/scene.h"

namespace multiray {

// Largest coordinate magnitude accepted for eye and target, scene units. Rays start at the
// eye and Embree needs org + t·dir finite over the scene; 1e18 leaves room for scenes up
// to ~1e19 across without overflowing float (max ~3.4e38) in products and dot products.
// Scene vertices have the same limit (validate() in scene.h).
constexpr float kMaxCameraCoordinate = kMaxSceneCoordinate;

// Empty when `c` is usable; otherwise one line saying what is wrong: a non-finite or
// too-large coordinate, eye == target (or too close to normalise the view direction), an
// up vector of zero length or parallel to the view direction, fov outside (0, 180).
std::string camera_problem(const Camera& c);

}  // namespace multiray
