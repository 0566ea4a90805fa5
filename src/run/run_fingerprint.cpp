#include "run/run_fingerprint.h"

#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include <fmt/core.h>

namespace multiray {

namespace {

// The content hash of a regular file's bytes, read in 1 MiB blocks; nullopt when it cannot
// be read (the loaders report that themselves).
std::optional<uint64_t> hash_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::vector<char> block(size_t(1) << 20);
  uint64_t h = content_hash(nullptr, 0);
  while (in.read(block.data(), std::streamsize(block.size())) || in.gcount() > 0)
    h = content_hash(block.data(), size_t(in.gcount()), h);
  return h;
}

// An option's value as compared: a file's path may differ between machines (its content
// is hashed as it is read), so only its file name is shown; any other value as it is.
std::string shown(const std::string& value) {
  std::error_code ec;
  return std::filesystem::is_regular_file(value, ec)
             ? "'" + std::filesystem::path(value).filename().string() + "'"
             : value;
}

}  // namespace

void fingerprint_files(LoadOptions& load, const std::string& scene_path, PixelFingerprint& fp) {
  const std::string folder = std::filesystem::path(scene_path).parent_path().string() + "/";
  load.on_read = [folder, &fp](const std::string& path, uint64_t hash) {
    const bool under = folder.size() > 1 && path.compare(0, folder.size(), folder) == 0;
    const std::string name =
        under ? path.substr(folder.size()) : std::filesystem::path(path).filename().string();
    fp.push_back({"'" + name + "'", hash});
  };
}

void fingerprint_options(const RunConfig& o, bool volume_input, bool scene_sent,
                         PixelFingerprint& fp) {
  if (!scene_sent)
    fp.push_back({fmt::format("the scene options (--env {} --env-scale {} --sun {} --up {})",
                              shown(o.env), o.env_scale, o.sun, o.up),
                  0});
  if (!volume_input) return;
  fp.push_back({fmt::format("the volume options (--tf {} --step {} --raw {})", shown(o.volume.tf),
                            o.volume.step, o.volume.raw),
                0});
  for (const std::string& path : {o.scene_path, o.volume.tf})
    if (const std::optional<uint64_t> h = hash_file(path))
      fp.push_back({"'" + std::filesystem::path(path).filename().string() + "'", *h});
}

}  // namespace multiray
