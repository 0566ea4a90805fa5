// Loader helpers shared by the three formats: extension dispatch, one-line error
// messages and warnings, the final repair-and-validate step, and texture decoding (stb_image from
// Debian's libstb; the implementation is compiled into that library, so no
// STB_IMAGE_IMPLEMENTATION here).
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "scene/loaders.h"

namespace multiray {

namespace fs = std::filesystem;

Scene load_scene(const std::string& path, const LoadOptions& options) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path, options);
  if (ext == ".obj") return load_obj(path, options);
  if (ext == ".ply") return load_ply(path, options);
  if (ext == ".xml") return load_mitsuba(path, options);
  std::string assimp_list;
  for (const char* e : kAssimpExtensions) {
    if (ext == e) return load_assimp(path, options);
    assimp_list += std::string(", ") + e;
  }
  std::error_code ec;
  if (fs::is_directory(path, ec))
    detail::fail(path, "this is a folder; give a scene file (or a volume) inside it");
  if (ext == ".raw")
    detail::fail(path,
                 "a .raw file has no header: give its layout with --raw "
                 "NXxNYxNZ:TYPE (e.g. --raw 256x256x128:uint8) to render it as a volume");
  detail::fail(path, "unknown scene file extension '" + ext +
                         "' (supported: .gltf, .glb, .obj, .ply, .xml; through assimp:" +
                         assimp_list.substr(1) + ")");
}

namespace detail {

Vec3 shading_normal(Vec3 n) {
  const double x = n.x, y = n.y, z = n.z;
  const double len = std::sqrt(x * x + y * y + z * z);  // finite for any finite floats
  if (!std::isfinite(len) || !(len > 0)) return Vec3(std::numeric_limits<float>::quiet_NaN());
  return Vec3(float(x / len), float(y / len), float(z / len));
}

Vec3 flat_normal(Vec3 a, Vec3 b, Vec3 c) {
  const double u[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double v[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0) || !std::isfinite(len)) return Vec3(0, 0, 1);
  return Vec3(float(n[0] / len), float(n[1] / len), float(n[2] / len));
}

float to_float(double x) {
  if (std::isnan(x)) return std::numeric_limits<float>::quiet_NaN();
  if (x > double(FLT_MAX)) return std::numeric_limits<float>::infinity();
  if (x < -double(FLT_MAX)) return -std::numeric_limits<float>::infinity();
  return float(x);
}

namespace {

// Unit face normal of triangle `t`, or +z if an index is out of range.
Vec3 face_normal(const Scene& s, size_t t) {
  for (int k = 0; k < 3; ++k)
    if (s.indices[3 * t + size_t(k)] >= s.positions.size()) return Vec3(0, 0, 1);
  return flat_normal(s.positions[s.indices[3 * t]], s.positions[s.indices[3 * t + 1]],
                     s.positions[s.indices[3 * t + 2]]);
}

// Replaces every shading normal that is not a finite unit vector (the NaN that
// shading_normal() gives for a zero, NaN or infinite normal in the file) by the face
// normal of the first triangle using the vertex (+z for a vertex no triangle uses).
// Returns how many were replaced. Leaves scenes whose arrays do not match to validate().
size_t repair_normals(Scene* s) {
  if (s->normals.size() != s->positions.size()) return 0;
  auto bad = [](Vec3 n) {
    const float l = length(n);
    return !is_finite(n) || !(std::abs(l - 1.0f) < 1e-3f);
  };
  size_t count = 0;
  for (size_t t = 0; t < s->triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = s->indices[3 * t + size_t(k)];
      if (v >= s->normals.size() || !bad(s->normals[v])) continue;
      s->normals[v] = face_normal(*s, t);
      ++count;
    }
  for (Vec3& n : s->normals)
    if (bad(n)) n = Vec3(0, 0, 1), ++count;
  return count;
}

}  // namespace

void validate_loaded(Scene* scene, const std::string& path, const LoadOptions& options) {
  const size_t repaired = repair_normals(scene);
  try {
    validate(*scene);
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::string prefix = "scene '" + scene->name + "': ";
    if (what.compare(0, prefix.size(), prefix) == 0) what.erase(0, prefix.size());
    fail(path, what);
  }
  if (repaired > 0)  // only for scenes that load: one line, not one per vertex
    warn(options, path,
         std::to_string(repaired) +
             " shading normal(s) were zero, NaN or infinite; replaced by face normals");
}

std::string pixels_text(int64_t width, int64_t height) {
  return " (" + std::to_string(width) + " x " + std::to_string(height) + " pixels)";
}

bool decode_texture(const unsigned char* bytes, size_t size, Texture* out,
                    const LoadOptions& options, const std::string& what, TexelCoding coding) {
  if (bytes == nullptr || size == 0 || size > size_t(INT_MAX)) return false;
  int w = 0, h = 0, n = 0;
  // Measure before decoding: a 100-byte PNG may claim 2^31 x 2^31 pixels.
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &n) || w <= 0 || h <= 0 ||
      uint64_t(w) * uint64_t(h) > kMaxTexturePixels)
    return false;
  // The texels keep 4 bytes a pixel; while decoding, stb's RGBA copy (4 more) and the
  // decoder's own pixels in the file's n channels of up to 16 bits are held as well.
  const uint64_t pixels = uint64_t(w) * uint64_t(h);
  if (options.reserve_image)
    options.reserve_image(what + pixels_text(w, h), 4 * pixels,
                          pixels * (4 + 2 * uint64_t(std::clamp(n, 1, 4))));
  unsigned char* px = stbi_load_from_memory(bytes, int(size), &w, &h, &n, 4);
  if (px == nullptr) return false;
  const bool ok = w > 0 && h > 0;
  if (ok) *out = Texture::from_pixels(px, w, h, 4, coding);
  stbi_image_free(px);
  return ok;
}

}  // namespace detail
}  // namespace multiray
