// Enlarging a view rendered at a reduced image scale back to the output's size (frame-time
// targeting in image space, Bruder et al. 2017 §6, and the viewer while the camera moves).
#pragma once

#include "core/image.h"

namespace multiray {

// Bilinear interpolation of `from` at the centres of `to`'s pixels (any sizes, both at
// least 1 x 1): output pixel (x, y) samples `from` at ((x + 0.5) w_from / w_to - 0.5, the
// same in y), clamped to the outermost pixel centres. A function linear in x and y is
// reproduced exactly between those centres; equal sizes copy. The result depends only on
// the whole smaller image, so it is the same however the frame was split. An alpha channel
// is interpolated the same way (premultiplied colour stays premultiplied); none, none.
void upscale_bilinear(const Framebuffer& from, Framebuffer& to);

}  // namespace multiray
