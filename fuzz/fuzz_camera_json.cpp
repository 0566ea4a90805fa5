// Fuzz target of camera keyframe files (`--camera-path FILE.json`): the input is written
// to a file and read with CameraPath::from_json_file(), which must return a path or throw
// InputError. A path is then evaluated at a few frames: every camera it yields must be one
// camera_problem() accepts (CameraPath::at() promises so), and the first two are
// rendered (fuzz::render_and_check), which must give finite pixels.
#include <climits>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "scene/camera_check.h"
#include "scene/camera_path.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  fuzz::FileSet files;
  files.main = std::string_view(reinterpret_cast<const char*>(data), size);
  const auto path = fuzz::write_files(files, "camera.json");
  CameraPath camera_path;
  try {
    camera_path = CameraPath::from_json_file(path.string());
  } catch (const InputError&) {
    return 0;
  }
  int rendered = 0;
  for (int frame : {INT_MIN, -1, 0, 1, 2, 3, 5, 8, 13, 100, 1000, INT_MAX}) {
    const Camera c = camera_path.at(frame);
    // at() promises a camera camera_problem() accepts, spline overshoot or not.
    if (const std::string why = camera_problem(c); !why.empty())
      fuzz::fail("CameraPath::at(" + std::to_string(frame) + ") gives a camera that " +
                 "camera_problem() refuses: " + why);
    if (rendered++ < 2) fuzz::render_and_check(c, "path");  // two renders per input at most
  }
  return 0;
}
