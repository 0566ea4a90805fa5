// Fuzz target of the scene loaders: the input (with optional companion files, see
// split_files) is written to scene<ext> and loaded with load_scene(), the entry point
// `multiray render FILE` uses. The libFuzzer build makes one executable per format
// (fuzz_ply, fuzz_obj, fuzz_gltf, fuzz_glb; MULTIRAY_FUZZ_EXT=".ply" ...), the replay
// build (replay_main.cpp) one for the four, given the extension as the flag -ext=.ply.
// The loaders' contract (loaders.h): a validated Scene, or an InputError; anything else
// (another exception, a crash, a sanitizer report, an invalid scene) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "core/error.h"
#include "fuzz_support.h"
#include "scene/loaders.h"

#ifdef MULTIRAY_FUZZ_EXT
static const std::string main_name = "scene" MULTIRAY_FUZZ_EXT;
#else
static std::string main_name;  // "scene" + the value of -ext=, set before the first input

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  for (int i = 1; i < *argc; ++i)
    if (const std::string_view a = (*argv)[i]; a.starts_with("-ext="))
      main_name = "scene" + std::string(a.substr(5));
  if (main_name.empty()) {
    std::fputs("usage: fuzz_replay_loader -ext=.ply|.obj|.gltf|.glb FILE|FOLDER...\n", stderr);
    std::exit(2);
  }
  return 0;
}
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  const auto path = fuzz::write_files(fuzz::split_files(data, size), main_name);
  LoadOptions options;  // the defaults `multiray render` uses, minus the printed warnings
  options.warn = [](const std::string&) {};
  Scene scene;
  try {
    scene = load_scene(path.string(), options);
  } catch (const InputError&) {
    return 0;  // refused with a message: the contract
  }
  try {
    validate(scene);
  } catch (const InputError& e) {
    fuzz::fail(std::string("a loaded scene fails validate(): ") + e.what());
  }
  return 0;
}
