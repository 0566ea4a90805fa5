#include "scene/camera_rig.h"

namespace multiray {

std::vector<Camera> CameraRig::views(const Camera& c) const {
  const Vec3 forward = normalize(c.target - c.eye);
  const Vec3 right = normalize(cross(forward, c.up));
  const Vec3 up = cross(right, forward);
  std::vector<Camera> out;
  out.reserve(size_t(view_count()));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < columns; ++k) {
      const float dx = (float(k) - 0.5f * float(columns - 1)) * spacing;
      const float dy = (0.5f * float(rows - 1) - float(r)) * spacing;
      const Vec3 offset = right * dx + up * dy;
      Camera v = c;
      v.eye = c.eye + offset;
      v.target = c.target + offset;
      out.push_back(v);
    }
  return out;
}

std::vector<int> CameraRig::reference_views(int spacing) const {
  if (spacing <= 0) return {centre_view()};
  const auto picks = [&](int count) {
    std::vector<int> out;
    for (int i = (count / 2) % spacing; i < count; i += spacing) out.push_back(i);
    return out;
  };
  std::vector<int> views;
  for (int r : picks(rows))
    for (int k : picks(columns)) views.push_back(r * columns + k);
  return views;
}

}  // namespace multiray
