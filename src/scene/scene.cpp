#include "scene/scene.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace multiray {

Vec3 Texture::sample(Vec2 uv) const {
  if (width <= 0 || height <= 0) return Vec3(1.0f);
  // Texel centres sit at half-integers; fx lies in [-0.5, width - 0.5), so the left
  // neighbour is in [-1, width - 1] and wrapping needs a compare, not a (slow) modulo.
  const float fx = (uv.x - std::floor(uv.x)) * float(width) - 0.5f;
  const float fy = (uv.y - std::floor(uv.y)) * float(height) - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  int x0 = int(x0f), y0 = int(y0f);
  x0 = x0 < 0 ? width - 1 : std::min(x0, width - 1);
  y0 = y0 < 0 ? height - 1 : std::min(y0, height - 1);
  const int x1 = x0 + 1 < width ? x0 + 1 : 0, y1 = y0 + 1 < height ? y0 + 1 : 0;
  const Vec3* row0 = &texels[size_t(y0) * size_t(width)];
  const Vec3* row1 = &texels[size_t(y1) * size_t(width)];
  return lerp(lerp(row0[x0], row0[x1], tx), lerp(row1[x0], row1[x1], tx), ty);
}

Bounds3 Scene::bounds() const {
  Bounds3 b;
  for (uint32_t i : indices) b.extend(positions[i]);
  return b;
}

Camera Scene::default_camera(float aspect) const {
  const Bounds3 b = bounds();
  Camera cam;
  cam.fov_y_deg = 45.0f;
  const Vec3 c = b.center();
  const Vec3 e = b.extent();
  const float half_h = 0.5f * std::max(e.y, e.x / std::max(aspect, 1e-3f));
  const float dist = half_h / std::tan(0.5f * cam.fov_y_deg * kPi / 180.0f) + 0.5f * e.z;
  cam.target = c;
  cam.eye = c + Vec3(0, 0, dist * 1.1f);
  cam.up = Vec3(0, 1, 0);
  return cam;
}

void validate(const Scene& s) {
  const std::string where = "scene '" + s.name + "': ";
  if (s.indices.empty()) throw InputError(where + "contains no triangles");
  if (s.indices.size() % 3 != 0) throw InputError(where + "index count is not a multiple of 3");
  if (s.material_ids.size() != s.triangle_count())
    throw InputError(where + "material id count does not match triangle count");
  if (!s.normals.empty() && s.normals.size() != s.positions.size())
    throw InputError(where + "normal count does not match vertex count");
  if (!s.uvs.empty() && s.uvs.size() != s.positions.size())
    throw InputError(where + "uv count does not match vertex count");
  for (size_t i = 0; i < s.positions.size(); ++i)
    if (!is_finite(s.positions[i]))
      throw InputError(where + "vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
  for (size_t i = 0; i < s.normals.size(); ++i)
    if (!is_finite(s.normals[i]))
      throw InputError(where + "normal " + std::to_string(i) + " is NaN or infinite");
  for (size_t i = 0; i < s.uvs.size(); ++i)
    if (!std::isfinite(s.uvs[i].x) || !std::isfinite(s.uvs[i].y))
      throw InputError(where + "uv " + std::to_string(i) + " is NaN or infinite");
  for (size_t i = 0; i < s.indices.size(); ++i)
    if (s.indices[i] >= s.positions.size())
      throw InputError(where + "triangle " + std::to_string(i / 3) + " uses vertex " +
                       std::to_string(s.indices[i]) + " but there are only " +
                       std::to_string(s.positions.size()));
  for (size_t t = 0; t < s.material_ids.size(); ++t)
    if (s.material_ids[t] >= s.materials.size())
      throw InputError(where + "triangle " + std::to_string(t) + " uses material " +
                       std::to_string(s.material_ids[t]) + " that does not exist");
  for (const Material& m : s.materials)
    if (m.base_color_texture >= int(s.textures.size()))
      throw InputError(where + "material '" + m.name + "' refers to a missing texture");
  bool any_area = false;
  for (size_t t = 0; t < s.triangle_count() && !any_area; ++t) {
    const Vec3 a = s.positions[s.indices[3 * t]], b = s.positions[s.indices[3 * t + 1]],
               c = s.positions[s.indices[3 * t + 2]];
    any_area = length(cross(b - a, c - a)) > 0.0f;
  }
  if (!any_area) throw InputError(where + "every triangle has zero area");
}

}  // namespace multiray
