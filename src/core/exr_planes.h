// One OpenEXR writer for every float image the project writes (write_exr, and the beauty
// with its feature buffers, aov_exr.h): single-part scanline, ZIP, 32-bit float channels,
// written atomically (file_io.h). Internal to core/.
#pragma once

#include <string>
#include <vector>

namespace multiray {

// A channel: the float at base[i * stride] is pixel i's value (row-major, width x height).
struct ExrPlane {
  std::string channel;
  const float* base;
  size_t stride;
};

// Throws InputError naming the path when it cannot be written.
void write_exr_planes(const std::string& path, int width, int height,
                      const std::vector<ExrPlane>& planes);

}  // namespace multiray
