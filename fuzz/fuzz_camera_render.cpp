// Fuzz target of camera checking and rendering: the input's first 40 bytes are ten floats
// (eye xyz, target xyz, up xyz, vertical fov in degrees, native byte order; shorter inputs
// are padded with zeros), an optional 41st byte picks the kernel (path, ao, depth). A
// camera that camera_problem() refuses is fine; one it accepts must render the built-in
// Cornell box with finite pixels only (fuzz::render_and_check). The bytes of a camera are
// easy to write: fuzz/README.md shows how.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_support.h"
#include "scene/camera_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  float f[10] = {};
  std::memcpy(f, data, size < sizeof f ? size : sizeof f);
  Camera c;
  c.eye = Vec3(f[0], f[1], f[2]);
  c.target = Vec3(f[3], f[4], f[5]);
  c.up = Vec3(f[6], f[7], f[8]);
  c.fov_y_deg = f[9];
  if (!camera_problem(c).empty()) return 0;
  static const char* const kKernels[] = {"path", "ao", "depth"};
  const char* kernel = size > sizeof f ? kKernels[data[sizeof f] % 3] : "path";
  fuzz::render_and_check(c, kernel);
  return 0;
}
