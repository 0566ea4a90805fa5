// How far an image is from a reference (Bruder et al. 2017, Table 4 compare their
// adaptation spaces this way): mean squared error and PSNR over linear RGB clamped to
// [0, 1], and SSIM (Wang et al. 2004) on the clamped luminance over 8x8 windows with a
// stride of 4, constants C1 = (0.01)^2, C2 = (0.03)^2 for a dynamic range of 1.
#pragma once

#include "core/image.h"

namespace multiray {

struct ImageError {
  double mse = 0;
  double psnr_db = 0;  // 10 log10(1 / mse); +inf for identical images
  double ssim = 1;     // in [-1, 1], 1 for identical images
};

// Throws std::invalid_argument when the sizes differ or an image is empty.
ImageError image_error(const Framebuffer& image, const Framebuffer& reference);

}  // namespace multiray
