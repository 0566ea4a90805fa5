#include "engine/orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace multiray {

namespace {

// Two unit vectors across `up`, for the yaw angle's origin.
void frame_of(Vec3 up, Vec3& a, Vec3& b) {
  a = std::abs(up.x) < 0.9f ? normalize(cross(up, Vec3{1, 0, 0}))
                            : normalize(cross(up, Vec3{0, 1, 0}));
  b = cross(up, a);
}

}  // namespace

OrbitCamera::OrbitCamera(const Camera& base, Vec3 up) : base_(base), up_(normalize(up)) {
  target_ = base.target;
  const Vec3 d = base.eye - base.target;
  distance_ = std::max(1e-6f, length(d));
  Vec3 a, b;
  frame_of(up_, a, b);
  const Vec3 dir = d / distance_;
  pitch_ = std::asin(std::clamp(dot(dir, up_), -1.0f, 1.0f));
  yaw_ = std::atan2(dot(dir, b), dot(dir, a));
  start_target_ = target_, start_distance_ = distance_, start_yaw_ = yaw_, start_pitch_ = pitch_;
}

void OrbitCamera::orbit(float yaw_deg, float pitch_deg) {
  yaw_ += yaw_deg * kPi / 180;
  const float limit = 89.0f * kPi / 180;
  pitch_ = std::clamp(pitch_ + pitch_deg * kPi / 180, -limit, limit);
}

void OrbitCamera::pan(float right, float up) {
  const Camera c = camera();
  const Vec3 forward = normalize(c.target - c.eye);
  const Vec3 r = normalize(cross(forward, up_));
  const Vec3 u = cross(r, forward);
  const float height = 2 * distance_ * std::tan(base_.fov_y_deg * kPi / 360);
  target_ = target_ + (r * right + u * up) * height;
}

void OrbitCamera::zoom(float factor) {
  distance_ = std::clamp(distance_ * factor, start_distance_ * 1e-4f, start_distance_ * 1e4f);
}

void OrbitCamera::look(float yaw_deg, float pitch_deg) {
  look_yaw_ = yaw_deg * kPi / 180;
  look_pitch_ = std::clamp(pitch_deg, -89.0f, 89.0f) * kPi / 180;
}

void OrbitCamera::reset() {
  target_ = start_target_, distance_ = start_distance_, yaw_ = start_yaw_, pitch_ = start_pitch_;
  look_yaw_ = look_pitch_ = 0;
}

Camera OrbitCamera::camera() const {
  Vec3 a, b;
  frame_of(up_, a, b);
  const Vec3 dir =
      (a * std::cos(yaw_) + b * std::sin(yaw_)) * std::cos(pitch_) + up_ * std::sin(pitch_);
  Camera c = base_;
  c.target = target_;
  c.eye = target_ + dir * distance_;
  c.up = up_;
  if (look_yaw_ == 0 && look_pitch_ == 0) return c;
  // Turn the view about the eye: the looking direction's own yaw and pitch, plus look()'s.
  const Vec3 view = -dir;
  const float pitch = std::clamp(std::asin(std::clamp(dot(view, up_), -1.0f, 1.0f)) + look_pitch_,
                                 -89.0f * kPi / 180, 89.0f * kPi / 180);
  const float yaw = std::atan2(dot(view, b), dot(view, a)) + look_yaw_;
  const Vec3 turned =
      (a * std::cos(yaw) + b * std::sin(yaw)) * std::cos(pitch) + up_ * std::sin(pitch);
  c.target = c.eye + turned * distance_;
  return c;
}

}  // namespace multiray
