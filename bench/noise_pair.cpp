// The noise of one renderer's image from two renders that differ only in their seed, for
// the equal-noise comparison with Cycles (bench/cycles_noise.sh): an image quality
// measurement, not a timing. With A and B independent estimates of the same image,
// (A - B)^2 / 2 is an unbiased estimate of one image's variance at that pixel and
// channel, so no reference image (and no renderer's bias) enters the figure.
//
// Usage: noise_pair A.exr B.exr
// Prints one JSON object: {"width", "height", "mean": [r, g, b] of (A + B) / 2,
//   "variance": the mean over pixels and channels of (A - B)^2 / 2,
//   "variance_rgb": the same per channel}.
// Exits 2 with one line when a file cannot be read or the sizes differ.
#include <cstdio>
#include <exception>

#include "core/image.h"

using namespace multiray;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: noise_pair A.exr B.exr\n");
    return 2;
  }
  try {
    const Framebuffer a = read_exr(argv[1]), b = read_exr(argv[2]);
    if (a.width != b.width || a.height != b.height) {
      std::fprintf(stderr, "noise_pair: %s is %dx%d but %s is %dx%d\n", argv[1], a.width, a.height,
                   argv[2], b.width, b.height);
      return 2;
    }
    double mean[3] = {0, 0, 0}, var[3] = {0, 0, 0};
    const size_t n = a.pixels.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec3 pa = a.pixels[i], pb = b.pixels[i];
      const double va[3] = {pa.x, pa.y, pa.z}, vb[3] = {pb.x, pb.y, pb.z};
      for (int c = 0; c < 3; ++c) {
        mean[c] += 0.5 * (va[c] + vb[c]);
        var[c] += 0.5 * (va[c] - vb[c]) * (va[c] - vb[c]);
      }
    }
    for (int c = 0; c < 3; ++c) mean[c] /= double(n), var[c] /= double(n);
    std::printf(
        "{\"width\": %d, \"height\": %d, \"mean\": [%.6g, %.6g, %.6g], \"variance\": %.6g, "
        "\"variance_rgb\": [%.6g, %.6g, %.6g]}\n",
        a.width, a.height, mean[0], mean[1], mean[2], (var[0] + var[1] + var[2]) / 3.0, var[0],
        var[1], var[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "noise_pair: %s\n", e.what());
    return 2;
  }
}
