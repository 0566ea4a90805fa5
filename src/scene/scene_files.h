// The one way the loaders read files: the scene file and every file it names go through a
// SceneFiles, which refuses what is not a regular file before opening it (a FIFO would
// block the load forever), keeps named files inside the scene file's folder unless
// LoadOptions::allow_outside, and charges every byte against LoadOptions::max_total_bytes.
// Private to src/scene.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/loaders.h"

namespace multiray::detail {

class SceneFiles {
 public:
  SceneFiles(const std::string& scene_path, const LoadOptions& options);

  // The scene file itself: a regular, non-empty file within the byte limit. Throws
  // InputError "<scene path>: <problem>" otherwise.
  std::string read_scene_file();

  // Reads `path`, a file the scene names, if it passes the checks (stat, never open):
  // exists, is a regular file, lies inside the scene's folder (symlinks and '..'
  // resolved) unless allow_outside, and fits in what is left of the byte limit. Its size
  // is then charged. Otherwise returns false and sets *why to one line naming `path`,
  // e.g. "'/m/fifo.bin' is not a regular file".
  bool read(const std::string& path, std::string* out, std::string* why);
  bool read(const std::string& path, std::vector<unsigned char>* out, std::string* why);

  const std::string& scene_path() const { return path_; }
  const LoadOptions& options() const { return options_; }

 private:
  template <class Bytes>
  bool read_checked(const std::string& path, bool named, Bytes* out, std::string* why);

  std::string path_;
  const LoadOptions& options_;
  std::filesystem::path root_;  // the scene file's folder, canonical; empty if unknown
  uint64_t used_ = 0;           // bytes read so far
};

}  // namespace multiray::detail
