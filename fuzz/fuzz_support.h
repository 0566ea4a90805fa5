// Helpers shared by the fuzz targets: a scratch folder for the files a loader must read,
// inputs that carry several files, and the render check of the camera targets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace multiray::fuzz {

// A private folder for the files a target writes: under $MULTIRAY_FUZZ_SCRATCH when set,
// else under /dev/shm when it exists (writing each input then costs no disk I/O), else
// under $TMPDIR or /tmp. Made on first use, removed at a normal exit; libFuzzer ends its
// runs with _Exit(), so fuzz/run.sh sets MULTIRAY_FUZZ_SCRATCH to a folder it removes.
const std::filesystem::path& scratch_dir();
// Removes everything inside scratch_dir().
void clear_scratch();
void write_file(const std::filesystem::path& path, std::string_view bytes);

// A fuzz input that carries several files: the main file, then any number of sections,
// each the line "@@file NAME" (after a line break) followed by that file's bytes up to the
// next section. fuzz/seed-corpus.sh packs an OBJ with its MTL files, or a glTF with its
// buffers and images, this way. Sections whose NAME is not a plain file name (empty,
// longer than 64 bytes, "." or "..", or holding '/' or a NUL) are dropped, so every file
// stays inside the scratch folder.
struct FileSet {
  std::string_view main;
  std::vector<std::pair<std::string, std::string_view>> others;  // name, bytes
};
FileSet split_files(const uint8_t* data, size_t size);

// Writes `files` into the (cleared) scratch folder, the main file as `main_name`, and
// returns the main file's path.
std::filesystem::path write_files(const FileSet& files, const std::string& main_name);

// Prints "multiray fuzz: <what>" and aborts, so libFuzzer keeps the input as a crash.
[[noreturn]] void fail(const std::string& what);

// Renders one small frame (kRenderWidth x kRenderHeight, 1 sample per pixel, at most 3
// bounces) of the built-in Cornell box seen by `camera`, with CPU kernel `kernel`, on one
// CPU device through a Session (the loop `multiray render` runs), and fails if any pixel is
// not finite. The caller has checked the camera with camera_problem().
constexpr int kRenderWidth = 8, kRenderHeight = 6;
void render_and_check(const Camera& camera, const std::string& kernel);

}  // namespace multiray::fuzz
