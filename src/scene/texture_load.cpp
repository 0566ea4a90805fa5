// Loader helpers shared by the three formats: extension dispatch, file reading, one-line
// error messages and texture decoding (stb_image from Debian's libstb; the
// implementation is compiled into that library, so no STB_IMAGE_IMPLEMENTATION here).
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "core/error.h"
#include "scene/loaders.h"

namespace multiray {

namespace fs = std::filesystem;

Scene load_scene(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
  if (ext == ".obj") return load_obj(path);
  if (ext == ".ply") return load_ply(path);
  detail::fail(path,
               "unknown scene file extension '" + ext + "' (supported: .gltf, .glb, .obj, .ply)");
}

namespace detail {

std::string file_name(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  return name.empty() ? path : name;
}

void fail(const std::string& path, const std::string& what) {
  std::string line;
  bool pending_break = false;
  for (char c : what) {
    if (c == '\n' || c == '\r') {
      pending_break = !line.empty();
      continue;
    }
    if (pending_break) line += "; ";
    pending_break = false;
    line += c;
  }
  throw InputError(path + ": " + line);
}

void validate_loaded(const Scene& scene, const std::string& path) {
  try {
    validate(scene);
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::string prefix = "scene '" + scene.name + "': ";
    if (what.compare(0, prefix.size(), prefix) == 0) what.erase(0, prefix.size());
    fail(path, what);
  }
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail(path, "file not found");
  if (!fs::is_regular_file(st)) fail(path, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file for reading");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, "read error");
  if (data.empty()) fail(path, "file is empty");
  return data;
}

bool decode_texture(const unsigned char* bytes, size_t size, Texture* out) {
  if (bytes == nullptr || size == 0 || size > size_t(INT_MAX)) return false;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load_from_memory(bytes, int(size), &w, &h, &n, 3);
  if (px == nullptr) return false;
  const bool ok = w > 0 && h > 0;
  if (ok) *out = Texture::from_srgb8(px, w, h, 3);
  stbi_image_free(px);
  return ok;
}

bool decode_texture_file(const std::string& path, Texture* out) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_texture(reinterpret_cast<const unsigned char*>(data.data()), data.size(), out);
}

}  // namespace detail
}  // namespace multiray
