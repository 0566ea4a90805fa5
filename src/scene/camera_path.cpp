#include "scene/camera_path.h"

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/camera_check.h"

namespace multiray {

CameraPath CameraPath::fixed(const Camera& cam) {
  CameraPath p;
  p.kind_ = Kind::Fixed;
  p.base_ = cam;
  return p;
}

CameraPath CameraPath::orbit(const Camera& base, float period_frames) {
  if (!std::isfinite(period_frames) || !(period_frames >= kMinOrbitPeriod)) {
    char got[32];
    std::snprintf(got, sizeof got, "%g", double(period_frames));
    throw InputError(std::string("camera orbit: the period must be a finite number of frames ") +
                     ">= 0.001 (got " + got + ")");
  }
  if (const std::string problem = camera_problem(base); !problem.empty())
    throw InputError("camera orbit: " + problem);
  CameraPath p;
  p.kind_ = Kind::Orbit;
  p.base_ = base;
  p.period_ = period_frames;
  return p;
}

CameraPath CameraPath::keyframes(std::vector<Keyframe> keys) {
  if (keys.empty()) throw InputError("camera path has no keyframes");
  for (size_t i = 0; i < keys.size(); ++i) {
    const std::string where = "camera path keyframe " + std::to_string(i) + ": ";
    if (!std::isfinite(keys[i].frame)) throw InputError(where + "the frame is not finite");
    if (const std::string problem = camera_problem(keys[i].camera); !problem.empty())
      throw InputError(where + problem);
  }
  for (size_t i = 1; i < keys.size(); ++i)
    if (!(keys[i].frame > keys[i - 1].frame))
      throw InputError("camera path keyframes must have increasing frame numbers");
  CameraPath p;
  p.kind_ = Kind::Keys;
  p.keys_ = std::move(keys);
  return p;
}

namespace {

Vec3 catmull_rom(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, float t) {
  const float t2 = t * t, t3 = t2 * t;
  return (p1 * 2.0f + (p2 - p0) * t + (p0 * 2.0f - p1 * 5.0f + p2 * 4.0f - p3) * t2 +
          (p1 * 3.0f - p0 - p2 * 3.0f + p3) * t3) *
         0.5f;
}

// JSON number `j` as a float; InputError unless it is finite as a float (1e39 is a fine
// double but an infinite float, and casting it is undefined behaviour).
float read_float(const nlohmann::json& j, const std::string& what, const std::string& where) {
  if (!j.is_number()) throw InputError(where + ": '" + what + "' must be a number");
  const double d = j.get<double>();
  if (!std::isfinite(d) || std::abs(d) > double(FLT_MAX))
    throw InputError(where + ": '" + what + "' is not a finite float");
  return float(d);
}

Vec3 read_vec3(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    throw InputError(where + ": '" + key + "' must be an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = read_float(j[key][size_t(i)], key, where);
  return v;
}

}  // namespace

CameraPath CameraPath::from_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open camera path '" + path + "'");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError("camera path '" + path + "' is not valid JSON");
  }
  return from_json(j, path);
}

CameraPath CameraPath::from_json(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object() || !j.contains("keyframes") || !j["keyframes"].is_array())
    throw InputError("camera path '" + path + "' needs a \"keyframes\" array");
  std::vector<Keyframe> keys;
  for (size_t i = 0; i < j["keyframes"].size(); ++i) {
    const auto& k = j["keyframes"][i];
    const std::string where = "camera path '" + path + "' keyframe " + std::to_string(i);
    if (!k.is_object() || !k.contains("frame") || !k["frame"].is_number())
      throw InputError(where + ": needs a numeric 'frame'");
    Keyframe kf;
    kf.frame = read_float(k["frame"], "frame", where);
    kf.camera.eye = read_vec3(k, "eye", where);
    kf.camera.target = read_vec3(k, "target", where);
    kf.camera.up = k.contains("up") ? read_vec3(k, "up", where) : Vec3(0, 1, 0);
    kf.camera.fov_y_deg = k.contains("fov") ? read_float(k["fov"], "fov", where) : 45.0f;
    if (!(kf.camera.fov_y_deg > 0 && kf.camera.fov_y_deg < 180))
      throw InputError(where + ": 'fov' must be between 0 and 180 degrees");
    if (const std::string problem = camera_problem(kf.camera); !problem.empty())
      throw InputError(where + ": " + problem);
    keys.push_back(kf);
  }
  try {
    return keyframes(std::move(keys));
  } catch (const InputError& e) {
    throw InputError("'" + path + "': " + e.what());
  }
}

Camera CameraPath::at(int frame) const {
  switch (kind_) {
    case Kind::Fixed:
      return base_;
    case Kind::Orbit: {
      // The phase in double, reduced first: finite for every int frame and period >=
      // kMinOrbitPeriod, and exactly 0 at whole revolutions.
      const double turns = std::fmod(double(frame), double(period_)) / double(period_);
      const double angle = 2.0 * double(kPi) * turns;
      const float cs = float(std::cos(angle)), sn = float(std::sin(angle));
      // About the world axis nearest the camera's up (y unless --up said otherwise).
      const Vec3 a(std::abs(base_.up.x), std::abs(base_.up.y), std::abs(base_.up.z));
      const int axis = a.y >= a.x && a.y >= a.z ? 1 : a.z >= a.x ? 2 : 0;
      auto turn = [&](Vec3 d) {
        if (axis == 2) return Vec3(cs * d.x - sn * d.y, sn * d.x + cs * d.y, d.z);
        if (axis == 0) return Vec3(d.x, cs * d.y - sn * d.z, sn * d.y + cs * d.z);
        return Vec3(cs * d.x + sn * d.z, d.y, -sn * d.x + cs * d.z);
      };
      Camera c = base_;
      c.eye = base_.target + turn(base_.eye - base_.target);
      c.up = turn(base_.up);
      return c;
    }
    case Kind::Keys: {
      const float f = float(frame);
      if (f <= keys_.front().frame) return keys_.front().camera;
      if (f >= keys_.back().frame) return keys_.back().camera;
      size_t i = 0;
      while (keys_[i + 1].frame < f) ++i;
      const float t = (f - keys_[i].frame) / (keys_[i + 1].frame - keys_[i].frame);
      const Camera& b = keys_[i].camera;
      const Camera& c = keys_[i + 1].camera;
      // Beyond the ends, phantom keys mirror the neighbour, so motion at a constant speed
      // stays exactly linear.
      auto before = [&](auto member) {
        return i > 0 ? keys_[i - 1].camera.*member : b.*member * 2.0f - c.*member;
      };
      auto after = [&](auto member) {
        return i + 2 < keys_.size() ? keys_[i + 2].camera.*member : c.*member * 2.0f - b.*member;
      };
      Camera out;
      out.eye = catmull_rom(before(&Camera::eye), b.eye, c.eye, after(&Camera::eye), t);
      out.target =
          catmull_rom(before(&Camera::target), b.target, c.target, after(&Camera::target), t);
      out.up = normalize(lerp(b.up, c.up, t));
      out.fov_y_deg = b.fov_y_deg + (c.fov_y_deg - b.fov_y_deg) * t;
      if (camera_problem(out).empty()) return out;
      // The spline overshot into an unusable camera: linear, else the nearer key.
      out.eye = lerp(b.eye, c.eye, t);
      out.target = lerp(b.target, c.target, t);
      if (camera_problem(out).empty()) return out;
      return t < 0.5f ? b : c;
    }
  }
  return base_;
}

}  // namespace multiray
