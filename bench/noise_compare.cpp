// Image noise against a reference (docs/noise.md): an image quality measurement, not a
// timing. For each IMAGE.exr, over every pixel and channel of the linear radiance:
//   rel_rmse  sqrt(mean((image - reference)^2)) / mean(reference)
//   bias      (mean(image) - mean(reference)) / mean(reference)
//   bias<X    the same over the pixels whose reference has every component <= X only
//             (with --below X: leaves out what --clamp X cuts by design, such as an emitter
//             seen directly)
//   max       the largest component of any pixel of the image
// The reference should be rendered with another --seed than the images: with the same
// seed a pixel's first N samples are the reference's own, and the error would shrink.
//
// Usage: noise_compare REFERENCE.exr [--below X] IMAGE.exr...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/image.h"

using namespace multiray;

namespace {

struct Noise {
  double rel_rmse = 0, bias = 0, bias_below = 0, max = 0;
};

// Sums over `fb`'s channels where `keep(pixel)`.
template <class Keep>
double channel_sum(const Framebuffer& fb, Keep keep) {
  double s = 0;
  for (size_t i = 0; i < fb.pixels.size(); ++i)
    if (keep(i)) s += double(fb.pixels[i].x) + fb.pixels[i].y + fb.pixels[i].z;
  return s;
}

Noise compare(const Framebuffer& img, const Framebuffer& ref, double below) {
  const auto all = [](size_t) { return true; };
  const auto under = [&](size_t i) { return max_component(ref.pixels[i]) <= below; };
  const double n = 3.0 * double(ref.pixels.size());
  const double ref_mean = channel_sum(ref, all) / n;
  double sq = 0, mx = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    const Vec3 d = img.pixels[i] - ref.pixels[i];
    sq += double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
    mx = std::max(mx, double(max_component(img.pixels[i])));
  }
  Noise r;
  r.rel_rmse = std::sqrt(sq / n) / ref_mean;
  r.bias = (channel_sum(img, all) - channel_sum(ref, all)) / n / ref_mean;
  const double ref_below = channel_sum(ref, under);
  r.bias_below = ref_below > 0 ? (channel_sum(img, under) - ref_below) / ref_below : 0;
  r.max = mx;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: noise_compare REFERENCE.exr [--below X] IMAGE.exr...\n");
    return 2;
  }
  try {
    const Framebuffer ref = read_exr(argv[1]);
    double below = INFINITY;
    std::printf("%-40s %9s %9s %9s %9s\n", "image", "rel_rmse", "bias", "bias<X", "max");
    for (int a = 2; a < argc; ++a) {
      if (std::string(argv[a]) == "--below" && a + 1 < argc) {
        below = std::atof(argv[++a]);
        continue;
      }
      const Framebuffer img = read_exr(argv[a]);
      if (img.width != ref.width || img.height != ref.height)
        throw std::runtime_error(std::string(argv[a]) + ": not the reference's size");
      const Noise r = compare(img, ref, below);
      std::printf("%-40s %8.2f%% %+8.2f%% %+8.2f%% %9.3f\n", argv[a], 100 * r.rel_rmse,
                  100 * r.bias, 100 * r.bias_below, r.max);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "noise_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
