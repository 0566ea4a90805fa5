// Environment maps: Radiance RGBE (.hdr) through stb_image, OpenEXR (.exr) through the
// OpenEXR library's RGBA interface. Both are read as linear RGB floats.
#include <ImfArray.h>
#include <ImfRgbaFile.h>
#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/scene_files.h"
#include "scene/loaders.h"

namespace multiray {

namespace {

namespace fs = std::filesystem;

void check_size(const std::string& path, int64_t w, int64_t h) {
  if (w <= 0 || h <= 0 || uint64_t(w) * uint64_t(h) > detail::kMaxTexturePixels)
    detail::fail(path, "environment map of " + std::to_string(w) + " x " + std::to_string(h) +
                           " pixels (the limit is " + std::to_string(detail::kMaxTexturePixels) +
                           " pixels)");
}

// Charges a map of w x h pixels against options.reserve_image before it is decoded: its
// radiance keeps 12 bytes a pixel, the decoder's pixels take `decoder_bytes` more.
void reserve(const std::string& path, const LoadOptions& options, int64_t w, int64_t h,
             uint64_t decoder_bytes) {
  const uint64_t pixels = uint64_t(w) * uint64_t(h);
  if (options.reserve_image)
    options.reserve_image(path + ": environment map" + detail::pixels_text(w, h),
                          pixels * sizeof(Vec3), pixels * decoder_bytes);
}

void read_hdr(const std::string& path, const LoadOptions& options, const std::string& bytes,
              EnvironmentMap* map) {
  if (bytes.size() > size_t(INT_MAX)) detail::fail(path, "file too large");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  int w = 0, h = 0, n = 0;
  if (!stbi_info_from_memory(data, int(bytes.size()), &w, &h, &n))
    detail::fail(path, std::string("not a readable image: ") + stbi_failure_reason());
  check_size(path, w, h);
  reserve(path, options, w, h, 3 * sizeof(float));
  float* px = stbi_loadf_from_memory(data, int(bytes.size()), &w, &h, &n, 3);
  if (px == nullptr) detail::fail(path, std::string("cannot decode: ") + stbi_failure_reason());
  map->width = w, map->height = h;
  map->radiance.resize(size_t(w) * size_t(h));
  for (size_t i = 0; i < map->radiance.size(); ++i)
    map->radiance[i] = Vec3(px[3 * i], px[3 * i + 1], px[3 * i + 2]);
  stbi_image_free(px);
}

void read_exr(const std::string& path, const LoadOptions& options, EnvironmentMap* map) {
  try {
    Imf::RgbaInputFile file(path.c_str());  // reads the header only
    const Imath::Box2i dw = file.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    check_size(path, w, h);
    reserve(path, options, w, h, sizeof(Imf::Rgba));
    Imf::Array2D<Imf::Rgba> px(h, w);
    file.setFrameBuffer(&px[0][0] - dw.min.x - dw.min.y * w, 1, size_t(w));
    file.readPixels(dw.min.y, dw.max.y);
    map->width = int(w), map->height = int(h);
    map->radiance.resize(size_t(w) * size_t(h));
    for (int64_t y = 0; y < h; ++y)
      for (int64_t x = 0; x < w; ++x) {
        const Imf::Rgba& p = px[y][x];
        map->radiance[size_t(y * w + x)] = Vec3(float(p.r), float(p.g), float(p.b));
      }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    detail::fail(path, std::string("not a readable OpenEXR file: ") + e.what());
  }
}

}  // namespace

EnvironmentMap load_environment_map(const std::string& path, const LoadOptions& options) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".hdr" && ext != ".exr")
    detail::fail(path, "unknown environment map extension '" + ext + "' (supported: .hdr, .exr)");
  // The same checks as a scene file (regular, non-empty, within the byte limit) before
  // either library opens it.
  SceneFiles files(path, options);
  const std::string bytes = files.read_scene_file();
  EnvironmentMap map;
  map.name = detail::file_name(path);
  if (ext == ".hdr")
    read_hdr(path, options, bytes, &map);
  else
    read_exr(path, options, &map);
  // Radiance must be finite and non-negative for the sampling tables; anything else
  // (half-float infinities, negative values from some tools) becomes 0, with one warning.
  size_t bad = 0;
  for (Vec3& c : map.radiance)
    for (int k = 0; k < 3; ++k)
      if (!(c[k] >= 0) || !std::isfinite(c[k])) c[k] = 0, ++bad;
  if (bad > 0)
    detail::warn(options, path,
                 std::to_string(bad) + " negative or non-finite values were set to 0");
  return map;
}

}  // namespace multiray
