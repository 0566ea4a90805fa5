#include "run/ar_setup.h"

#include <cmath>

#include "core/error.h"
#include "run/parse_options.h"
#include "scene/ar_poses.h"

namespace multiray {

void parse_ground(const std::string& text, RenderSettings& settings) {
  settings.catcher_axis = -1;
  if (text.empty()) return;
  const std::string usage = "--ground '" + text + "' must look like y=0 or y=0,albedo=0.5";
  const size_t eq = text.find('=');
  if (eq != 1 || (text[0] != 'x' && text[0] != 'y' && text[0] != 'z')) throw InputError(usage);
  const size_t comma = text.find(',');
  const double height =
      to_number(text.substr(2, comma == std::string::npos ? std::string::npos : comma - 2),
                "--ground height");
  if (!std::isfinite(height) || std::abs(height) > 1e18)
    throw InputError("--ground: the height must be a finite number");
  float albedo = 0.5f;
  if (comma != std::string::npos) {
    const std::string rest = text.substr(comma + 1);
    if (rest.rfind("albedo=", 0) != 0) throw InputError(usage);
    const double a = to_number(rest.substr(7), "--ground albedo");
    if (!(a >= 0 && a <= 1)) throw InputError("--ground: albedo must be in [0, 1]");
    albedo = float(a);
  }
  settings.catcher_axis = text[0] - 'x';
  settings.catcher_height = float(height);
  settings.catcher_albedo = albedo;
}

std::string ground_conflict(const RunConfig& o, const std::string& kernel, bool volume_input) {
  if (volume_input) return "--ground: volumes have no shadow catcher (meshes only)";
  if (kernel != "path")
    return "--ground works with the path integrator, not --integrator " + kernel;
  if (o.sampling == "foveated" || o.sampling == "reproject")
    return "--ground works with uniform or adaptive sampling, not --sampling " + o.sampling;
  if (o.views != "1x1" || o.stereo > 0)
    return "--ground renders one view (no --views or --stereo)";
  if (o.distributed.enabled)
    return "--ground does not run on other ranks yet (their results carry no alpha)";
  return "";
}

CameraPath poses_path(const RunConfig& o, int width, int height) {
  if (o.camera_path != "fixed")
    throw InputError("--poses and --camera-path " + o.camera_path + " both move the camera");
  const ArPoses poses = read_ar_poses(o.poses);
  const double theirs = double(poses.width) / poses.height, ours = double(width) / height;
  if (std::abs(theirs / ours - 1) > 0.01)
    throw InputError("--poses: the capture's images are " + std::to_string(poses.width) + "x" +
                     std::to_string(poses.height) + ", an aspect ratio --res " +
                     std::to_string(width) + "x" + std::to_string(height) + " does not have");
  if (o.frames > int(poses.cameras.size()))
    throw InputError("--frames " + std::to_string(o.frames) + " is more than the " +
                     std::to_string(poses.cameras.size()) + " poses of --poses '" + o.poses +
                     "' (pose i is frame i)");
  return poses.path();
}

int pose_count(const std::string& path) { return int(read_ar_poses(path).cameras.size()); }

}  // namespace multiray
