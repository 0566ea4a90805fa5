#include "scene/ar_poses.h"

#include <cmath>
#include <fstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/camera_check.h"

namespace multiray {

namespace {

std::vector<float> numbers(const nlohmann::json& j, const char* key, size_t n,
                           const std::string& where) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != n)
    throw InputError(where + ": needs \"" + key + "\", " + std::to_string(n) + " numbers");
  std::vector<float> v;
  for (const auto& x : j[key]) {
    const double d = x.is_number() ? x.get<double>() : NAN;
    if (!std::isfinite(d) || std::abs(d) > 1e30)
      throw InputError(where + ": \"" + key + "\" holds something other than a finite number");
    v.push_back(float(d));
  }
  return v;
}

// The camera of column-major camera-to-world matrix `m` (-Z forward, +Y up).
Camera camera_of(const std::vector<float>& m, float fov_y_deg, const std::string& where) {
  const Vec3 x(m[0], m[1], m[2]), y(m[4], m[5], m[6]), z(m[8], m[9], m[10]);
  const Vec3 t(m[12], m[13], m[14]);
  const float tol = 1e-3f;
  if (std::abs(m[3]) > tol || std::abs(m[7]) > tol || std::abs(m[11]) > tol ||
      std::abs(m[15] - 1) > tol)
    throw InputError(where + ": the transform's last row must be 0 0 0 1");
  if (std::abs(length(x) - 1) > tol || std::abs(length(y) - 1) > tol ||
      std::abs(length(z) - 1) > tol || std::abs(dot(x, y)) > tol || std::abs(dot(y, z)) > tol ||
      std::abs(dot(x, z)) > tol || dot(cross(x, y), z) < 0)
    throw InputError(where +
                     ": the transform's rotation is not a rotation (columns must be "
                     "orthonormal and right-handed)");
  Camera c;
  c.eye = t;
  c.target = t - z;
  c.up = y;
  c.fov_y_deg = fov_y_deg;
  if (const std::string why = camera_problem(c); !why.empty())
    throw InputError(where + ": " + why);
  return c;
}

}  // namespace

CameraPath ArPoses::path() const {
  std::vector<Keyframe> keys;
  for (size_t i = 0; i < cameras.size(); ++i) keys.push_back(Keyframe{float(i), cameras[i]});
  return CameraPath::keyframes(std::move(keys));
}

ArPoses read_ar_poses(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open --poses '" + path + "'");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception&) {
    throw InputError("--poses '" + path + "' is not valid JSON");
  }
  return ar_poses_from_json(j, path);
}

ArPoses ar_poses_from_json(const nlohmann::json& j, const std::string& source) {
  const std::string file = "--poses '" + source + "'";
  if (!j.is_object() || !j.contains("poses") || !j["poses"].is_array() || j["poses"].empty())
    throw InputError(file + " needs a non-empty \"poses\" array");
  if (j["poses"].size() > 1000000) throw InputError(file + ": more than 1000000 poses");
  ArPoses out;
  const std::vector<float> image = numbers(j, "image", 2, file);
  if (image[0] != std::floor(image[0]) || image[1] != std::floor(image[1]) || image[0] < 1 ||
      image[1] < 1 || image[0] > 65536 || image[1] > 65536)
    throw InputError(file + ": \"image\" must be a width and a height in 1..65536 pixels");
  out.width = int(image[0]), out.height = int(image[1]);
  for (size_t i = 0; i < j["poses"].size(); ++i) {
    const auto& p = j["poses"][i];
    const std::string where = file + " pose " + std::to_string(i);
    if (!p.is_object()) throw InputError(where + ": must be an object");
    const std::vector<float> k = numbers(p.contains("intrinsics") ? p : j, "intrinsics", 4, where);
    const float fx = k[0], fy = k[1], cx = k[2], cy = k[3];
    if (!(fx > 0 && fy > 0)) throw InputError(where + ": focal lengths must be > 0 pixels");
    if (std::abs(fx / fy - 1) > 0.01f)
      throw InputError(where + ": fx and fy differ by more than 1% (non-square pixels)");
    if (std::abs(cx - 0.5f * image[0]) > 0.02f * image[0] ||
        std::abs(cy - 0.5f * image[1]) > 0.02f * image[1])
      throw InputError(where + ": the principal point is more than 2% of the image off centre");
    const float fov = 2.0f * std::atan(0.5f * image[1] / fy) * 180.0f / kPi;
    if (!(fov >= kMinPoseFovDeg))
      throw InputError(where + ": a focal length of " + fmt::format("{:g}", fy) +
                       " pixels is a field of view of " + fmt::format("{:g}", fov) +
                       " degrees (at least " + fmt::format("{:g}", kMinPoseFovDeg) +
                       "; are the intrinsics in pixels?)");
    out.cameras.push_back(camera_of(numbers(p, "transform", 16, where), fov, where));
  }
  return out;
}

nlohmann::json ar_poses_to_json(const std::vector<Camera>& cameras, int width, int height) {
  const float fy = 0.5f * float(height) /
                   std::tan(0.5f * (cameras.empty() ? 45.0f : cameras[0].fov_y_deg) * kPi / 180);
  nlohmann::json poses = nlohmann::json::array();
  for (const Camera& c : cameras) {
    const Vec3 z = normalize(c.eye - c.target), x = normalize(cross(c.up, z)), y = cross(z, x);
    const float f = 0.5f * float(height) / std::tan(0.5f * c.fov_y_deg * kPi / 180);
    poses.push_back(
        {{"transform",
          {x.x, x.y, x.z, 0, y.x, y.y, y.z, 0, z.x, z.y, z.z, 0, c.eye.x, c.eye.y, c.eye.z, 1}},
         {"intrinsics", {f, f, 0.5f * width, 0.5f * height}}});
  }
  return {{"image", {width, height}},
          {"intrinsics", {fy, fy, 0.5f * width, 0.5f * height}},
          {"poses", poses}};
}

}  // namespace multiray
