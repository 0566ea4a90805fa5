// Image error measures against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "core/image_metrics.h"

namespace multiray {
namespace image_metrics_test {

Framebuffer gradient(int w, int h) {
  Framebuffer fb(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) fb.at(x, y) = Vec3(float(x) / w, float(y) / h, 0.5f);
  return fb;
}

TEST(ImageError, IdenticalImages) {
  const Framebuffer a = gradient(32, 24);
  const ImageError e = image_error(a, a);
  EXPECT_EQ(e.mse, 0);
  EXPECT_TRUE(std::isinf(e.psnr_db));
  EXPECT_NEAR(e.ssim, 1, 1e-12);
}

TEST(ImageError, ConstantOffsetGivesKnownMseAndPsnr) {
  const Framebuffer a = gradient(32, 24);
  Framebuffer b = a;
  for (Vec3& p : b.pixels) p.z += 0.3f;  // 0.5 -> 0.8 in one channel of three
  const ImageError e = image_error(b, a);
  EXPECT_NEAR(e.mse, 0.09 / 3, 1e-6);
  EXPECT_NEAR(e.psnr_db, 10 * std::log10(3 / 0.09), 1e-3);
  EXPECT_LT(e.ssim, 1.0);
}

TEST(ImageError, NoiseLowersSsimMoreThanABlur) {
  const Framebuffer a = gradient(64, 48);
  Framebuffer noisy = a, shifted = a;
  for (size_t i = 0; i < noisy.pixels.size(); ++i) {
    const float n = (i * 2654435761u % 1000) / 1000.0f - 0.5f;
    noisy.pixels[i] = noisy.pixels[i] + Vec3(0.4f * n);
    shifted.pixels[i] = shifted.pixels[i] + Vec3(0.01f);
  }
  EXPECT_LT(image_error(noisy, a).ssim, 0.8);
  EXPECT_GT(image_error(shifted, a).ssim, 0.99);
}

TEST(ImageError, ValuesAreClampedAndSizesChecked) {
  Framebuffer a(4, 4), b(4, 4);
  for (Vec3& p : b.pixels) p = Vec3(5.0f);  // clamps to 1
  EXPECT_NEAR(image_error(b, a).mse, 1.0, 1e-12);
  for (Vec3& p : b.pixels) p = Vec3(NAN);  // NaN counts as 0
  EXPECT_EQ(image_error(b, a).mse, 0);
  EXPECT_THROW(image_error(Framebuffer(4, 4), Framebuffer(4, 5)), std::invalid_argument);
  EXPECT_THROW(image_error(Framebuffer(), Framebuffer()), std::invalid_argument);
}

}  // namespace image_metrics_test
}  // namespace multiray
