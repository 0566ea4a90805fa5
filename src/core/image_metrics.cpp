#include "core/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace multiray {

namespace {
float clamped(float x) { return std::clamp(std::isfinite(x) ? x : 0.0f, 0.0f, 1.0f); }

std::vector<double> clamped_luminance(const Framebuffer& fb) {
  std::vector<double> out(fb.pixels.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec3& p = fb.pixels[i];
    out[i] = luminance(Vec3(clamped(p.x), clamped(p.y), clamped(p.z)));
  }
  return out;
}

// Mean SSIM over 8x8 windows at a stride of 4 (one window when the image is smaller).
double mean_ssim(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
  constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  const int win_w = std::min(8, w), win_h = std::min(8, h);
  double sum = 0;
  int windows = 0;
  for (int y0 = 0; y0 + win_h <= h; y0 += 4)
    for (int x0 = 0; x0 + win_w <= w; x0 += 4) {
      double ma = 0, mb = 0, va = 0, vb = 0, cov = 0;
      const double n = double(win_w) * win_h;
      for (int y = y0; y < y0 + win_h; ++y)
        for (int x = x0; x < x0 + win_w; ++x)
          ma += a[size_t(y) * w + x], mb += b[size_t(y) * w + x];
      ma /= n, mb /= n;
      for (int y = y0; y < y0 + win_h; ++y)
        for (int x = x0; x < x0 + win_w; ++x) {
          const double da = a[size_t(y) * w + x] - ma, db = b[size_t(y) * w + x] - mb;
          va += da * da, vb += db * db, cov += da * db;
        }
      va /= n - 1, vb /= n - 1, cov /= n - 1;
      sum += (2 * ma * mb + c1) * (2 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++windows;
    }
  return windows > 0 ? sum / windows : 1.0;
}
}  // namespace

ImageError image_error(const Framebuffer& image, const Framebuffer& reference) {
  if (image.width != reference.width || image.height != reference.height || image.pixels.empty() ||
      image.pixels.size() != reference.pixels.size())
    throw std::invalid_argument("image_error: images of different or zero size");
  ImageError e;
  double sq = 0;
  for (size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(clamped(image.pixels[i][c])) - clamped(reference.pixels[i][c]);
      sq += d * d;
    }
  e.mse = sq / (3.0 * double(image.pixels.size()));
  e.psnr_db = e.mse > 0 ? 10 * std::log10(1 / e.mse) : std::numeric_limits<double>::infinity();
  e.ssim =
      mean_ssim(clamped_luminance(image), clamped_luminance(reference), image.width, image.height);
  return e;
}

}  // namespace multiray
