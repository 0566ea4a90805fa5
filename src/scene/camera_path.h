// Camera animation. A path is a pure function of the frame number, so any device, process
// or re-run computes the same camera for frame f.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scene/scene.h"

namespace multiray {

struct Keyframe {
  float frame = 0;  // may be fractional
  Camera camera;
};

class CameraPath {
 public:
  // Shortest orbit period accepted, frames: shorter ones turn the angle into noise, and
  // below ~1e-38 into infinity (NaN cameras).
  static constexpr float kMinOrbitPeriod = 1e-3f;

  // A still camera.
  static CameraPath fixed(const Camera& cam);
  // Orbit around `base.target` about the world axis nearest `base.up` (the horizontal
  // plane of a y-up scene, of a z-up one with --up z) through base.eye, one revolution
  // every `period_frames` frames, starting at base.eye; the up vector turns with the
  // eye, so every frame's camera is a rotated copy of `base`. Throws InputError when
  // the period is not finite or below kMinOrbitPeriod, or camera_problem() rejects base.
  static CameraPath orbit(const Camera& base, float period_frames);
  // Keyframes interpolated with Catmull-Rom splines through eye and target (linear for
  // fov and up), clamped at the ends. Keyframes must have finite, increasing frame
  // numbers and cameras camera_problem() accepts; InputError "camera path keyframe <i>:
  // <problem>" otherwise.
  static CameraPath keyframes(std::vector<Keyframe> keys);
  // Reads {"keyframes":[{"frame":0,"eye":[x,y,z],"target":[...],"up":[...],"fov":45},...]}.
  // Throws InputError "camera path '<path>' keyframe <i>: <problem>" (or naming just
  // the file) for bad JSON, numbers that are not finite as floats, and cameras
  // camera_problem() rejects.
  static CameraPath from_json_file(const std::string& path);
  // The same document already parsed; messages name `source` where they name the file
  // ("camera path '<source>' keyframe <i>: <problem>").
  static CameraPath from_json(const nlohmann::json& doc, const std::string& source);

  // The camera of frame `frame`. Always one camera_problem() accepts: between two valid
  // keyframes the spline can still overshoot into an unusable camera (eye and target
  // paths crossing make eye == target; opposite up vectors interpolate through zero),
  // and then the frame gets the linear interpolation of the two keys, or if that is
  // unusable too, the nearer key.
  Camera at(int frame) const;

 private:
  enum class Kind { Fixed, Orbit, Keys } kind_ = Kind::Fixed;
  Camera base_;
  float period_ = 100;
  std::vector<Keyframe> keys_;
};

}  // namespace multiray
