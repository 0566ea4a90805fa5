// Camera poses of an augmented-reality capture (--poses): one pose and its intrinsics per
// frame of the real images, in a JSON format close to what ARKit (ARCamera.transform,
// .intrinsics, .imageResolution) and ARCore (Camera.getPose().toMatrix, CameraIntrinsics)
// export. docs/ar.md documents it:
//
//   {"image": [W, H],                       the size the intrinsics are in, pixels
//    "intrinsics": [fx, fy, cx, cy],        default for every pose, pixels
//    "poses": [{"transform": [16 numbers],  camera to world, column-major (ARKit's
//                                            simd_float4x4, OpenGL's order); the camera
//                                            looks along its -Z, +Y up, +X right
//               "intrinsics": [...]},        optional, this pose's own
//              ...]}
//
// Pose i is frame i (a run of more frames than poses is refused: run/ar_setup.h). Pixels
// are taken as square and the principal point as the image centre; intrinsics that say
// otherwise by more than 1% (fx against fy) or 2% of the image (cx, cy) are refused rather
// than rendered with the wrong perspective, and so is a vertical field of view under
// kMinPoseFovDeg.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scene/camera_path.h"
#include "scene/scene.h"

namespace multiray {

// The narrowest vertical field of view a pose may have, degrees. Below it neighbouring
// pixels' rays differ by less than ~10 float epsilons at phone resolutions (the image
// turns to one colour); no phone or camera lens is that narrow (a 1e30-pixel focal
// length, 1e-28 degrees, is a unit error).
constexpr float kMinPoseFovDeg = 0.1f;

struct ArPoses {
  int width = 0, height = 0;    // of the images the intrinsics refer to
  std::vector<Camera> cameras;  // one per frame

  // The cameras as a path whose frame i is cameras[i] (held after the last).
  CameraPath path() const;
};

// Reads the file; InputError "--poses '<path>' pose <i>: <problem>" (or naming the file
// alone) for bad JSON, missing or non-finite numbers, a transform that is not a rotation
// and translation, and intrinsics outside the limits above.
ArPoses read_ar_poses(const std::string& path);
// The same document already parsed; messages name `source`.
ArPoses ar_poses_from_json(const nlohmann::json& doc, const std::string& source);

// The pose document of `cameras` (the inverse of ar_poses_from_json, up to rounding), with
// intrinsics for images of width x height: for making test captures from a camera path.
nlohmann::json ar_poses_to_json(const std::vector<Camera>& cameras, int width, int height);

}  // namespace multiray
