// The one way the loaders read files: the scene file and every file it names go through a
// SceneFiles, which refuses what is not a regular file before opening it (a FIFO would
// block the load forever), keeps named files inside the scene file's folder unless
// LoadOptions::allow_outside, and charges every byte against LoadOptions::max_total_bytes.
// In core because scene and volume loaders share it (a volume never includes the scene).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace multiray {

// What a load may read, and where its warnings go. The defaults are the safe choice for
// files from anywhere: every file is checked with stat() before it is opened, so a FIFO,
// device or directory is refused without ever being opened (it could block forever).
struct LoadOptions {
  // Files the scene file names (glTF buffers and images, OBJ material libraries and
  // textures) are read only if they lie inside the scene file's folder after symlinks
  // and '..' are resolved. True lifts that restriction (never the regular-file one).
  bool allow_outside = false;
  // Bytes one load may read: the scene file plus every file it names, together.
  uint64_t max_total_bytes = uint64_t(4) << 30;  // 4 GiB
  // Receives one line per thing the load dropped but could do without (a refused
  // image or material library, repaired normals, an unusable camera). Unset: printed to
  // stderr as "multiray: warning: <line>".
  std::function<void(const std::string& line)> warn;
  // Called before an image (texture, environment map) is decoded, once its header has
  // given its size: `what` names it ("<scene file>: image 'a.png' (16000 x 16000
  // pixels)"), `keep` is what its pixels will hold for as long as the scene lives and
  // `transient` what decoding takes on top of that while it runs, in bytes. Throws
  // InputError to refuse the load: a run charges images against --max-memory
  // (run/run.cpp). Unset: only the loaders' pixel cap applies.
  std::function<void(const std::string& what, uint64_t keep, uint64_t transient)> reserve_image;
  // Bytes a third-party parser that cannot be checked first (assimp) may take while it
  // reads the scene: it reads it first in a child process limited to this much
  // (scene/assimp_trial.h). 0: no limit, no child. A run sets --max-memory's budget.
  uint64_t parser_memory_limit = 0;
  // Called with every file a load has read (the scene file, each file it names, an
  // environment map) and content_hash() of its bytes: what a distributed run compares
  // between ranks (distributed/fingerprint.h). Unset: nothing is hashed.
  std::function<void(const std::string& path, uint64_t hash)> on_read;
};

// FNV-1a (64 bit) of `size` bytes, continuing from `seed`: a file's content fingerprint
// (not cryptographic: it tells a stale copy from the right one, not an attacker's).
uint64_t content_hash(const void* data, size_t size, uint64_t seed = 0xcbf29ce484222325ull);

// Helpers every loader (scene and volume) shares.
namespace detail {
// `path` with directories removed, for Scene::name and messages.
std::string file_name(const std::string& path);

// Throws InputError "<path>: <what>", with line breaks in `what` folded into "; " so the
// message stays one line (library error strings often end in '\n').
[[noreturn]] void fail(const std::string& path, const std::string& what);

// Sends "<path>: <what>" to options.warn (or stderr).
void warn(const LoadOptions& options, const std::string& path, const std::string& what);

}  // namespace detail

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

}  // namespace multiray
