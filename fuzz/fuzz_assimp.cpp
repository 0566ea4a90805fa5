// Fuzz target of the formats read through assimp (kAssimpExtensions, load_assimp.cpp). The
// first byte of the input picks the extension (its value modulo the number of
// extensions); the rest is the scene file with optional companion files (split_files),
// written as scene<ext> and loaded with load_scene(), the entry point `multiray render
// FILE` uses. The contract is the loaders' (loaders.h): a validated Scene or an
// InputError. Debian's libassimp is not instrumented: the sanitizers see its memory
// errors only where they reach multiray's code or the heap, and libFuzzer's coverage
// guidance comes from multiray's side of the load (what assimp's scene holds). An
// abort() inside assimp is a finding like any crash (docs/reliability.md). Quick3D inputs
// (.q3o, .q3s) are skipped unless MULTIRAY_FUZZ_KNOWN is set: assimp's Quick3D reader can
// take all memory on a 2-byte change of a sample file (open finding F6).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "scene/loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  if (size < 1) return 0;
  constexpr size_t kFormats = std::size(kAssimpExtensions);
  const std::string ext = kAssimpExtensions[data[0] % kFormats];
  static const bool known = std::getenv("MULTIRAY_FUZZ_KNOWN") != nullptr;
  if (!known && (ext == ".q3o" || ext == ".q3s")) return -1;  // F6; -1: not kept in the corpus
  const auto path = fuzz::write_files(fuzz::split_files(data + 1, size - 1), "scene" + ext);
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
