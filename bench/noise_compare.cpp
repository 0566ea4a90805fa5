// Image noise against a reference (docs/noise.md): an image quality measurement, not a
// timing. For each IMAGE.exr:
//   png_rmse  RMSE of the 8-bit sRGB values a PNG of it holds against the reference's PNG,
//             in levels of 255 (both with the reference's metered exposure and the filmic
//             curve, render's defaults for meshes): the noise as the PNG shows it
//   specks    pixels of that PNG with a channel kSpeck or more levels above the
//             reference's: fireflies as one sees them
//   rel_rmse  RMSE of the linear radiance, over every pixel and channel, / the reference's
//             mean: dominated by whatever is brightest (the light, its reflection)
//   bias      (mean(image) - mean(reference)) / mean(reference), linear radiance
//   bias*     the same without the pixels where EXCLUDE.exr is not black (a render with
//             --bounces 0 is the emitters seen directly, which --clamp cuts by design and
//             which would otherwise decide the figure)
// The reference should be rendered with another --seed than the images: with the same
// seed a pixel's first N samples are the reference's own, and the error would shrink.
//
// Usage: noise_compare REFERENCE.exr EXCLUDE.exr IMAGE.exr...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/exposure.h"
#include "core/image.h"

using namespace multiray;

namespace {

// A channel this many levels of 255 above the reference's makes a visible speck.
constexpr int kSpeck = 48;

struct Noise {
  double png_rmse = 0, rel_rmse = 0, bias = 0, bias_kept = 0;
  size_t specks = 0;
};

double channel_sum(Vec3 v) { return double(v.x) + v.y + v.z; }

// `keep`: the pixels bias* counts; `d`: how both PNGs are made.
Noise compare(const Framebuffer& img, const Framebuffer& ref, const std::vector<bool>& keep,
              const Display& d) {
  double sum_img = 0, sum_ref = 0, sq = 0, kept_img = 0, kept_ref = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    const Vec3 a = img.pixels[i], r = ref.pixels[i], e = a - r;
    sum_img += channel_sum(a), sum_ref += channel_sum(r);
    sq += channel_sum(e * e);
    if (keep[i]) kept_img += channel_sum(a), kept_ref += channel_sum(r);
  }
  const double n = 3.0 * double(ref.pixels.size());
  const std::vector<uint8_t> png_img = to_srgb8(img, d), png_ref = to_srgb8(ref, d);
  double png_sq = 0;
  size_t specks = 0;
  for (size_t i = 0; i < png_ref.size(); i += 3) {
    bool speck = false;
    for (size_t c = i; c < i + 3; ++c) {
      const int e = int(png_img[c]) - int(png_ref[c]);
      png_sq += double(e) * e;
      speck |= e >= kSpeck;
    }
    specks += speck;
  }
  return {std::sqrt(png_sq / double(png_ref.size())), std::sqrt(sq / n) / (sum_ref / n),
          (sum_img - sum_ref) / sum_ref, (kept_img - kept_ref) / kept_ref, specks};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: noise_compare REFERENCE.exr EXCLUDE.exr IMAGE.exr...\n");
    return 2;
  }
  try {
    const Framebuffer ref = read_exr(argv[1]), exclude = read_exr(argv[2]);
    const auto check_size = [&](const Framebuffer& f, const char* name) {
      if (f.width != ref.width || f.height != ref.height)
        throw std::runtime_error(std::string(name) + ": not the reference's size");
    };
    check_size(exclude, argv[2]);
    std::vector<bool> kept(ref.pixels.size());
    size_t left_out = 0;
    for (size_t i = 0; i < kept.size(); ++i)
      left_out += !(kept[i] = !(max_component(exclude.pixels[i]) > 0));
    const Display d{metered_exposure_ev(ref), ToneCurve::Filmic};
    std::printf(
        "PNGs at %+.2f EV, filmic; bias* without the %zu of %zu pixels where %s is "
        "not black\n",
        d.exposure_ev, left_out, kept.size(), argv[2]);
    std::printf("%-36s %9s %7s %9s %9s %9s\n", "image", "png_rmse", "specks", "rel_rmse", "bias",
                "bias*");
    for (int a = 3; a < argc; ++a) {
      const Framebuffer img = read_exr(argv[a]);
      check_size(img, argv[a]);
      const Noise r = compare(img, ref, kept, d);
      std::printf("%-36s %9.2f %7zu %8.1f%% %+8.2f%% %+8.2f%%\n", argv[a], r.png_rmse, r.specks,
                  100 * r.rel_rmse, 100 * r.bias, 100 * r.bias_kept);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "noise_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
