// Denoised and raw images against a reference (issue 52, docs/noise.md): an image quality
// measurement, not a timing. For each IMAGE.exr, against REFERENCE.exr (another seed):
//   rel_rmse   RMSE of the linear radiance over every pixel and channel, / the
//              reference's mean (the figure the goals compare)
//   edge_rmse  the same over the reference's edge pixels only: where its displayed
//              luminance changes by more than kEdge between 4-neighbours (edges and
//              texture detail a filter may blur)
//   png_rmse   RMSE of the 8-bit sRGB values of both PNGs, levels of 255
//   ssim       SSIM (core/image_metrics.h) of the two PNGs' values
//   black      share of pixels black in the image's PNG (every channel 0) but not in the
//              reference's: the salt and pepper of a few samples in a dim hall
// Both PNGs use the reference's metered exposure plus EV (default 0) and the filmic curve.
//
// Usage: denoise_compare [--ev X] REFERENCE.exr IMAGE.exr...
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/exposure.h"
#include "core/image.h"
#include "core/image_metrics.h"

using namespace multiray;

namespace {

constexpr double kEdge = 0.08;  // displayed luminance step, of 1, that makes an edge pixel

struct Quality {
  double rel_rmse = 0, edge_rmse = 0, png_rmse = 0, ssim = 0, black = 0;
};

// The PNG's values as a [0, 1] image, for SSIM and the edge map.
Framebuffer displayed(const std::vector<uint8_t>& png, int width, int height) {
  Framebuffer f;
  f.width = width, f.height = height;
  f.pixels.resize(png.size() / 3);
  for (size_t i = 0; i < f.pixels.size(); ++i)
    f.pixels[i] = {png[3 * i] / 255.0f, png[3 * i + 1] / 255.0f, png[3 * i + 2] / 255.0f};
  return f;
}

std::vector<bool> edge_pixels(const Framebuffer& shown) {
  const int w = shown.width, h = shown.height;
  std::vector<bool> edge(shown.pixels.size(), false);
  auto lum = [&](int x, int y) {
    return luminance(shown.pixels[size_t(y) * size_t(w) + size_t(x)]);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double l = lum(x, y);
      double step = 0;
      if (x + 1 < w) step = std::max(step, std::abs(lum(x + 1, y) - l));
      if (x > 0) step = std::max(step, std::abs(lum(x - 1, y) - l));
      if (y + 1 < h) step = std::max(step, std::abs(lum(x, y + 1) - l));
      if (y > 0) step = std::max(step, std::abs(lum(x, y - 1) - l));
      edge[size_t(y) * size_t(w) + size_t(x)] = step > kEdge;
    }
  return edge;
}

Quality compare(const Framebuffer& img, const Framebuffer& ref, const std::vector<bool>& edge,
                const Display& d) {
  double sum_ref = 0, sq = 0, edge_sq = 0, edge_ref = 0;
  size_t edges = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    const Vec3 r = ref.pixels[i], e = img.pixels[i] - r;
    const double s = double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z;
    sum_ref += double(r.x) + r.y + r.z, sq += s;
    if (edge[i]) edge_sq += s, edge_ref += double(r.x) + r.y + r.z, ++edges;
  }
  const double n = 3.0 * double(ref.pixels.size()), mean = sum_ref / n;
  const std::vector<uint8_t> a = to_srgb8(img, d), b = to_srgb8(ref, d);
  double png_sq = 0;
  size_t black = 0;
  for (size_t i = 0; i < b.size(); i += 3) {
    for (size_t c = i; c < i + 3; ++c)
      png_sq += double(int(a[c]) - int(b[c])) * (int(a[c]) - int(b[c]));
    black += (a[i] | a[i + 1] | a[i + 2]) == 0 && (b[i] | b[i + 1] | b[i + 2]) != 0;
  }
  Quality q;
  q.rel_rmse = std::sqrt(sq / n) / mean;
  q.edge_rmse =
      edges ? std::sqrt(edge_sq / (3.0 * double(edges))) / (edge_ref / (3.0 * double(edges))) : 0;
  q.png_rmse = std::sqrt(png_sq / double(b.size()));
  q.ssim =
      image_error(displayed(a, img.width, img.height), displayed(b, ref.width, ref.height)).ssim;
  q.black = double(black) / double(ref.pixels.size());
  return q;
}

}  // namespace

int main(int argc, char** argv) {
  int first = 1;
  double ev = 0;
  if (argc > 2 && std::string(argv[1]) == "--ev") ev = std::atof(argv[2]), first = 3;
  if (argc - first < 2) {
    std::fprintf(stderr, "usage: denoise_compare [--ev X] REFERENCE.exr IMAGE.exr...\n");
    return 2;
  }
  try {
    const Framebuffer ref = read_exr(argv[first]);
    const Display d{float(metered_exposure_ev(ref) + ev), ToneCurve::Filmic};
    const std::vector<bool> edge = edge_pixels(displayed(to_srgb8(ref, d), ref.width, ref.height));
    size_t edges = 0;
    for (bool e : edge) edges += e;
    std::printf("PNGs at %+.2f EV, filmic; %zu of %zu pixels are edges of the reference\n",
                d.exposure_ev, edges, edge.size());
    std::printf("%-40s %9s %9s %9s %7s %7s\n", "image", "rel_rmse", "edge_rmse", "png_rmse",
                "ssim", "black");
    for (int a = first + 1; a < argc; ++a) {
      const Framebuffer img = read_exr(argv[a]);
      if (img.width != ref.width || img.height != ref.height)
        throw std::runtime_error(std::string(argv[a]) + ": not the reference's size");
      const Quality q = compare(img, ref, edge, d);
      std::printf("%-40s %8.1f%% %8.1f%% %9.2f %7.4f %6.2f%%\n", argv[a], 100 * q.rel_rmse,
                  100 * q.edge_rmse, q.png_rmse, q.ssim, 100 * q.black);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "denoise_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
