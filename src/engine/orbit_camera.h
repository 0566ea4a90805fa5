// A camera the mouse (or a head pose) moves interactively: orbiting its target about the
// scene's up axis, panned and zoomed. Used by the live viewer; pure, no session.
#pragma once

#include "scene/scene.h"

namespace multiray {

// A camera orbiting its target about the scene's up axis, panned and zoomed by the mouse;
// starts from `base` (its eye, target and fov).
class OrbitCamera {
 public:
  OrbitCamera(const Camera& base, Vec3 up);
  // Degrees: yaw about the up axis, pitch towards it (kept within 89 degrees of level).
  void orbit(float yaw_deg, float pitch_deg);
  // Moves eye and target across the view by fractions of the view's height at the target.
  void pan(float right, float up);
  // Multiplies the distance to the target by `factor` (kept within 1e-4 .. 1e4 of the
  // starting distance).
  void zoom(float factor);
  // Augmented reality: the device's orientation relative to where it started, degrees.
  // The view turns about the eye (the target moves, the eye stays), yaw about the up axis
  // and pitch towards it, as a phone held up turns its camera; absolute, not summed.
  void look(float yaw_deg, float pitch_deg);
  void reset();
  Camera camera() const;

 private:
  Camera base_;
  Vec3 up_, target_;
  float distance_ = 1, start_distance_ = 1, yaw_ = 0, pitch_ = 0;  // yaw, pitch in radians
  Vec3 start_target_;
  float start_yaw_ = 0, start_pitch_ = 0;
  float look_yaw_ = 0, look_pitch_ = 0;  // radians, look()
};

}  // namespace multiray
