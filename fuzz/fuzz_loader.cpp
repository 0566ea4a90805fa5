// Fuzz target of the scene loaders: the input (with optional companion files, see
// split_files) is written to scene<MULTIRAY_FUZZ_EXT> and loaded with load_scene(), the
// entry point `multiray render FILE` uses. Built once per format (fuzz_ply, fuzz_obj,
// fuzz_gltf, fuzz_glb). The loaders' contract (loaders.h): a validated Scene, or an
// InputError; anything else (another exception, a crash, a sanitizer report, an invalid
// scene) is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "scene/loaders.h"

#ifndef MULTIRAY_FUZZ_EXT
#error "define MULTIRAY_FUZZ_EXT, e.g. \".ply\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  const auto path = fuzz::write_files(fuzz::split_files(data, size), "scene" MULTIRAY_FUZZ_EXT);
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
