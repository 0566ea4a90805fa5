// Camera animation. A path is a pure function of the frame number, so any device, process
// or re-run computes the same camera for frame f.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace multiray {

struct Keyframe {
  float frame = 0;  // may be fractional
  Camera camera;
};

class CameraPath {
 public:
  // A still camera.
  static CameraPath fixed(const Camera& cam);
  // Orbit around `base.target` in the horizontal plane through base.eye, one revolution
  // every `period_frames` frames, starting at base.eye.
  static CameraPath orbit(const Camera& base, float period_frames);
  // Keyframes interpolated with Catmull-Rom splines through eye and target (linear for
  // fov and up), clamped at the ends. Keyframes must have increasing frame numbers.
  static CameraPath keyframes(std::vector<Keyframe> keys);
  // Reads {"keyframes":[{"frame":0,"eye":[x,y,z],"target":[...],"up":[...],"fov":45},...]}.
  // Throws InputError naming the file and the problem.
  static CameraPath from_json_file(const std::string& path);

  Camera at(int frame) const;

 private:
  enum class Kind { Fixed, Orbit, Keys } kind_ = Kind::Fixed;
  Camera base_;
  float period_ = 100;
  std::vector<Keyframe> keys_;
};

}  // namespace multiray
