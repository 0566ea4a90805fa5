// The beauty and its feature buffers (core/feature_buffers.h) as layers of one OpenEXR
// file, with the channel names other tools read:
//   R, G, B, A                 the beauty (linear radiance; A: 1, or the shadow catcher's
//                              coverage with premultiplied colour)
//   albedo.R, albedo.G, albedo.B
//   normal.X, normal.Y, normal.Z
//   depth.Z                    the layer "depth", channel Z: Nuke's own depth channel is
//                              named depth.Z, and Blender's multilayer reader splits a
//                              name at its last dot into layer and pass (a Z pass), as it
//                              writes its own Depth pass; a bare Z would sit in the beauty's
//                              layer, where Open Image Denoise front ends do not look.
//   variance.Y                 one channel: the variance of the pixel's mean luminance
//   emission.R, emission.G, emission.B
//                              the emitted radiance seen directly or through mirrors and
//                              glass (render/shared/aov.h): the part of the beauty a
//                              denoiser leaves sharp
// Single-part (scanline, ZIP, 32-bit float), so any OpenEXR reader back to version 1 takes
// it. Written atomically (core/file_io.h).
#pragma once

#include <string>
#include <vector>

#include "core/image.h"

namespace multiray {

// The channel names of AOV `name` (one of aov_names()), in file order.
std::vector<std::string> aov_channels(const std::string& name);

// Writes `fb` and the layers `aovs` (names from aov_names()) of fb.features to `path`.
// Throws InputError naming the path when it cannot be written, or when an AOV is asked for
// and fb.features is empty or of another size (nothing rendered them).
void write_exr_with_aovs(const std::string& path, const Framebuffer& fb,
                         const std::vector<std::string>& aovs);

}  // namespace multiray
