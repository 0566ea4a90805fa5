#include "scene/camera_check.h"

#include <algorithm>
#include <cmath>

namespace multiray {

namespace {
bool finite_and_bounded(const Vec3& v) {
  for (float x : {v.x, v.y, v.z})
    if (!std::isfinite(x) || std::abs(x) > kMaxCameraCoordinate) return false;
  return true;
}
}  // namespace

std::string camera_problem(const Camera& c) {
  if (!finite_and_bounded(c.eye)) return "the eye is not a finite point within 1e18 of the origin";
  if (!finite_and_bounded(c.target))
    return "the target is not a finite point within 1e18 of the origin";
  if (!(std::isfinite(c.up.x) && std::isfinite(c.up.y) && std::isfinite(c.up.z)))
    return "the up vector is not finite";
  if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180)) return "the fov must be in (0, 180) degrees";
  // Work in double: the difference of two bounded floats is finite there.
  const double dx = double(c.target.x) - c.eye.x, dy = double(c.target.y) - c.eye.y,
               dz = double(c.target.z) - c.eye.z;
  const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double scale = std::max(
      {std::abs(double(c.eye.x)), std::abs(double(c.eye.y)), std::abs(double(c.eye.z)), 1.0});
  if (!(len > 1e-6 * scale)) return "the eye and the target are (almost) the same point";
  const double ux = c.up.x, uy = c.up.y, uz = c.up.z;
  const double ulen = std::sqrt(ux * ux + uy * uy + uz * uz);
  if (!(ulen > 0)) return "the up vector has zero length";
  const double cx = dy * uz - dz * uy, cy = dz * ux - dx * uz, cz = dx * uy - dy * ux;
  if (!(std::sqrt(cx * cx + cy * cy + cz * cz) > 1e-6 * len * ulen))
    return "the up vector is parallel to the viewing direction";
  return "";
}

}  // namespace multiray
