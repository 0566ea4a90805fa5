#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "volume/volume.h"

namespace multiray {

namespace {

using Table = std::array<float, 256>;

// Exact sRGB decoding curve (IEC 61966-2-1) for the 256 byte values.
Table make_srgb_table() {
  Table t{};
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  }
  return t;
}

Table make_linear_table() {
  Table t{};
  for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i / 255.0);
  return t;
}

// See TexelCoding::signed_unit: 128 -> 0, 255 -> 1, 0 -> -1.
Table make_signed_table() {
  Table t{};
  for (int i = 0; i < 256; ++i)
    t[size_t(i)] = float(i >= 128 ? (i - 128) / 127.0 : (i - 128) / 128.0);
  return t;
}

Vec3 decode(uint32_t p, const float* lut) {
  return {lut[p & 0xff], lut[(p >> 8) & 0xff], lut[(p >> 16) & 0xff]};
}

}  // namespace

const float* texel_decoding_table(TexelCoding coding) {
  static const Table srgb = make_srgb_table(), linear = make_linear_table(),
                     signed_unit = make_signed_table();
  switch (coding) {
    case TexelCoding::linear:
      return linear.data();
    case TexelCoding::signed_unit:
      return signed_unit.data();
    default:
      return srgb.data();
  }
}

Texture Texture::from_pixels(const unsigned char* pixels, int width, int height, int channels,
                             TexelCoding coding) {
  Texture t;
  t.width = width;
  t.height = height;
  t.coding = coding;
  t.texels.resize(size_t(width) * size_t(height));
  const bool colour = channels >= 3;
  const bool alpha = channels == 2 || channels >= 4;
  for (size_t i = 0; i < t.texels.size(); ++i) {
    const unsigned char* p = pixels + i * size_t(channels);
    const uint32_t r = p[0], g = colour ? p[1] : p[0], b = colour ? p[2] : p[0];
    const uint32_t a = alpha ? p[colour ? 3 : 1] : 255u;
    t.texels[i] = r | g << 8 | b << 16 | a << 24;
  }
  return t;
}

Vec3 Texture::texel(int x, int y) const {
  return decode(texels[size_t(y) * size_t(width) + size_t(x)], texel_decoding_table(coding));
}

bool Texture::has_alpha() const {
  for (uint32_t p : texels)
    if ((p >> 24) != 255u) return true;
  return false;
}

Bounds3 Scene::bounds() const {
  Bounds3 b;
  if (volume && indices.empty()) {
    b.extend(volume->lower());
    b.extend(volume->lower() + volume->extent());
    return b;
  }
  for (uint32_t i : indices) b.extend(positions[i]);
  return b;
}

bool up_axis_vector(const std::string& name, Vec3& up) {
  std::string axis = name;
  float sign = 1.0f;
  if (!axis.empty() && (axis[0] == '+' || axis[0] == '-')) {
    sign = axis[0] == '-' ? -1.0f : 1.0f;
    axis.erase(0, 1);
  }
  if (axis != "x" && axis != "y" && axis != "z") return false;
  up = Vec3(0.0f);
  up[axis[0] - 'x'] = sign;
  return true;
}

bool fbx_up_axis(int up_axis, int up_axis_sign, Vec3& up) {
  if (up_axis < 0 || up_axis > 2 || (up_axis_sign != 1 && up_axis_sign != -1)) return false;
  up = Vec3(0.0f);
  up[up_axis] = float(up_axis_sign);
  return true;
}

Vec3 view_direction(Vec3 up, float azimuth_deg, float elevation_deg) {
  // Right is +x (+y when up is along x), flipped with up's sign; front = right x up is then
  // +z for +y up (glTF's convention) and -y for +z up (Blender's).
  const int axis = std::abs(up.x) > 0.5f ? 0 : std::abs(up.y) > 0.5f ? 1 : 2;
  const float sign = up[axis] < 0 ? -1.0f : 1.0f;
  Vec3 right(0.0f);
  right[axis == 0 ? 1 : 0] = sign;
  const Vec3 front = cross(right, up);
  const float az = azimuth_deg * kPi / 180.0f, el = elevation_deg * kPi / 180.0f;
  return normalize(front * (std::cos(el) * std::cos(az)) + right * (std::cos(el) * std::sin(az)) +
                   up * std::sin(el));
}

Camera Scene::default_camera(float aspect, Vec3 up, float azimuth_deg, float elevation_deg) const {
  const Bounds3 b = bounds();
  const Vec3 d = view_direction(up, azimuth_deg, elevation_deg);  // target towards the eye
  Camera cam;
  cam.fov_y_deg = kDefaultFovDeg;
  cam.target = b.center();
  cam.up = up;
  // The image basis PinholeCamera builds from this camera.
  const Vec3 f = -d, r = normalize(cross(f, up)), u = cross(r, f);
  const float tan_y = std::tan(0.5f * cam.fov_y_deg * kPi / 180.0f) * kDefaultMargin;
  const float tan_x = tan_y * std::max(aspect, 1e-6f);
  // A corner q (relative to the target) lies at depth dist - dot(q, d) in front of the eye
  // and inside the image when its offsets across are within tan * depth: the smallest
  // distance that holds for all eight corners.
  float dist = 0.0f, nearest = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y,
                      (i & 4) ? b.hi.z : b.lo.z);
    const Vec3 q = corner - cam.target;
    const float along = dot(q, d);
    dist =
        std::max(dist, along + std::max(std::abs(dot(q, r)) / tan_x, std::abs(dot(q, u)) / tan_y));
    nearest = std::max(nearest, along);
  }
  // Every corner strictly in front of the eye (so the eye is outside the bounds).
  dist = std::max(dist, nearest * 1.01f + 1e-6f * (1.0f + max_component(b.extent())));
  cam.eye = cam.target + d * dist;
  return cam;
}

void validate(const Scene& s) {
  const std::string where = "scene '" + s.name + "': ";
  if (s.volume) {
    if (!s.indices.empty()) throw InputError(where + "holds both triangles and a volume");
    return;  // checked by its loader (volume/load_volume.h)
  }
  if (s.indices.empty()) throw InputError(where + "contains no triangles");
  if (s.indices.size() % 3 != 0) throw InputError(where + "index count is not a multiple of 3");
  if (s.material_ids.size() != s.triangle_count())
    throw InputError(where + "material id count does not match triangle count");
  if (!s.normals.empty() && s.normals.size() != s.positions.size())
    throw InputError(where + "normal count does not match vertex count");
  if (!s.uvs.empty() && s.uvs.size() != s.positions.size())
    throw InputError(where + "uv count does not match vertex count");
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3 p = s.positions[i];
    if (!is_finite(p))
      throw InputError(where + "vertex " + std::to_string(i) +
                       " has a NaN or infinite coordinate");
    if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > kMaxSceneCoordinate) {
      char xyz[96];
      std::snprintf(xyz, sizeof xyz, "(%g, %g, %g)", p.x, p.y, p.z);
      throw InputError(where + "vertex " + std::to_string(i) + " at " + xyz +
                       " lies beyond 1e18 on some axis (the limit for scene coordinates)");
    }
  }
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
  for (const Material& m : s.materials) {
    for (int tex : {m.base_color_texture, m.emission_texture, m.metallic_roughness_texture,
                    m.normal_texture})
      if (tex >= int(s.textures.size()))
        throw InputError(where + "material '" + m.name + "' refers to a missing texture");
    if (!std::isfinite(m.normal_scale) || !(m.opacity >= 0 && m.opacity <= 1) ||
        !std::isfinite(m.alpha_cutoff))
      throw InputError(where + "material '" + m.name +
                       "' has a normal scale, opacity or alpha cutoff out of range");
  }
  bool any_area = false;
  for (size_t t = 0; t < s.triangle_count() && !any_area; ++t) {
    const Vec3 a = s.positions[s.indices[3 * t]], b = s.positions[s.indices[3 * t + 1]],
               c = s.positions[s.indices[3 * t + 2]];
    any_area = length(cross(b - a, c - a)) > 0.0f;
  }
  if (!any_area) throw InputError(where + "every triangle has zero area");
}

}  // namespace multiray
