// One iteration of the edge-avoiding à-trous filter for one pixel, and the spatial
// variance estimate it starts from when no variance is given (render/shared/denoise.h
// has the buffers, the guides and the credits). Written in render/shared/language.h's
// dialect: the CPU and OpenCL drivers call these per pixel.
#ifndef MULTIRAY_RENDER_SHARED_DENOISE_ATROUS_H
#define MULTIRAY_RENDER_SHARED_DENOISE_ATROUS_H

#ifdef __cplusplus
#include "render/shared/denoise.h"
#endif

MR_NAMESPACE_BEGIN

// The spatial variance estimate's sums over its window: of the taps' weights, their
// weighted luminances and weighted squared luminances.
typedef struct {
  float weight, m1, m2;
} DenoiseMoments;

MR_DEVICE void denoise_moments_add(DenoiseMoments* m, float g, float l) {
  m->weight += g;
  m->m1 += g * l;
  m->m2 += g * l * l;
}

// The variance the sums give: mean square minus squared mean (never negative).
MR_DEVICE float denoise_moments_variance(const DenoiseMoments* m) {
  // weight >= the centre's own weight, which is 1 up to rounding.
  const float m1 = m->m1 / m->weight;
  const float m2 = m->m2 / m->weight;
  return mr_fmax(0.0f, m2 - m1 * m1);
}

// The variance of the demodulated luminance around pixel (x, y): the luminance's mean and
// mean square over a (2 MR_DENOISE_VARIANCE_RADIUS + 1)^2 window, each pixel weighted by
// the guides (so the window keeps to the centre's surface), and their difference. The
// window's spread of the lighting itself counts as noise: an overestimate where the
// lighting changes, which only lets the colour weight blur a little more there.
// `luminance`: of the demodulated colour (denoise_store_luminance); `guides`, `slopes`:
// denoise_pack_guides's.
MR_DEVICE float denoise_spatial_variance(const MR_GLOBAL float* luminance,
                                         const MR_GLOBAL float* guides,
                                         const MR_GLOBAL float* slopes, int width, int height,
                                         int x, int y, const DenoiseWeights* w) {
  const int pixels = width * height;
  const DenoiseCentre centre = denoise_centre(guides, slopes, pixels, y * width + x, w);
  DenoiseMoments m;
  m.weight = 0.0f, m.m1 = 0.0f, m.m2 = 0.0f;
  for (int dy = -MR_DENOISE_VARIANCE_RADIUS; dy <= MR_DENOISE_VARIANCE_RADIUS; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -MR_DENOISE_VARIANCE_RADIUS; dx <= MR_DENOISE_VARIANCE_RADIUS; ++dx) {
      const int qx = x + dx;
      if (qx < 0 || qx >= width) continue;
      const int q = qy * width + qx;
      denoise_moments_add(&m, denoise_guide_weight(&centre, guides, pixels, q, dx, dy, w),
                          luminance[q]);
    }
  }
  return denoise_moments_variance(&m);
}

// Whether pixel i starts from the renderer's variance (`given`, scaled by
// denoise_demodulate) rather than the spatial estimate above: where one was given and it
// is not 0. A variance of 0 says nothing here: the renderer's needs two samples (a pixel
// of one sample, as most of an adaptive frame's are, has 0), and a black pixel whose
// samples all returned nothing says little about its mean at a few samples per pixel;
// yet taken as the noise, 0 makes the luminance weight shut out every neighbour that
// differs, and the pixel stays as it came (issue 52: the salt and pepper of the Sponza
// hall at 16 spp, the speckles of `--sampling adaptive`). Where two samples or more all
// agreed (a constant sky), the estimate among like neighbours is 0 too, and a region black
// throughout stays black.
MR_DEVICE int denoise_uses_given_variance(int has_variance, const MR_GLOBAL float* given, int i) {
  if (!has_variance) return 0;  // and `given` is not read (nothing wrote it)
  return given[i] != 0.0f;
}

// The variance the filter starts from at pixel (x, y): the given one or the spatial
// estimate (denoise_uses_given_variance).
MR_DEVICE float denoise_start_variance(int has_variance, const MR_GLOBAL float* given,
                                       const MR_GLOBAL float* luminance,
                                       const MR_GLOBAL float* guides,
                                       const MR_GLOBAL float* slopes, int width, int height, int x,
                                       int y, const DenoiseWeights* w) {
  const int i = y * width + x;
  if (denoise_uses_given_variance(has_variance, given, i)) return given[i];
  return denoise_spatial_variance(luminance, guides, slopes, width, height, x, y, w);
}

// The 3x3 Gaussian's weight at (dx, dy), dx and dy in -1..1: 1 2 1 / 2 4 2 / 1 2 1.
MR_DEVICE float denoise_blur_weight(int dx, int dy) {
  return (dx == 0 ? 2.0f : 1.0f) * (dy == 0 ? 2.0f : 1.0f);
}

// The variance at p blurred by a 3x3 Gaussian (over what lies inside the image): SVGF's
// guard against a noisy variance estimate stopping the filter.
MR_DEVICE float denoise_blurred_variance(const MR_GLOBAL float* variance, int width, int height,
                                         int x, int y) {
  float sum = 0.0f, total = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qx >= width || qy < 0 || qy >= height) continue;
      const float k = denoise_blur_weight(dx, dy);
      sum += k * variance[qy * width + qx];
      total += k;
    }
  return sum / total;
}

// What the luminance difference of a tap is multiplied by: 1 / (sigma_luminance times
// the standard deviation of the centre's noise, from its blurred variance). 1e-10: a
// noiseless image (variance 0) still divides by something, and its equal luminances give
// weight exp(0) = 1.
MR_DEVICE float denoise_luminance_scale(float blurred_variance, const DenoiseWeights* w) {
  return 1.0f / (w->sigma_luminance * mr_sqrt(blurred_variance) + 1e-10f);
}

// The terms of tap q's weight in an à-trous iteration for the centre c, whose luminance
// is `lp`: denoise_guide_terms's cosine and exponent, the exponent with the luminance's
// added (how many standard deviations of noise, `inv_scale`, the tap's luminance lies
// from the centre's), so that one exp serves them all.
MR_DEVICE float denoise_atrous_terms(const DenoiseCentre* c, float lp, float inv_scale,
                                     const MR_GLOBAL float* guides,
                                     const MR_GLOBAL float* luminance, int pixels, int q, int dx,
                                     int dy, float* exponent) {
  const float cosine = denoise_guide_terms(c, guides, pixels, q, dx, dy, exponent);
  *exponent -= mr_fabs(luminance[q] - lp) * inv_scale;
  return cosine;
}

// An à-trous pixel's sums over its taps: of the weights, the colours times their weights
// and the variances times their squared weights (the taps taken as independent).
typedef struct {
  float weight, r, g, b, variance;
} DenoiseSum;

// Adds tap q with weight k (0: adds nothing).
MR_DEVICE void denoise_sum_add(DenoiseSum* s, float k, const MR_GLOBAL float* color,
                               const MR_GLOBAL float* variance, int q) {
  s->weight += k;
  s->r += color[3 * q] * k;
  s->g += color[3 * q + 1] * k;
  s->b += color[3 * q + 2] * k;
  s->variance += k * k * variance[q];
}

// The filtered pixel p from its sums: colour and variance normalised by the weights,
// and the colour's luminance (for the next iteration's taps).
MR_DEVICE void denoise_sum_store(const DenoiseSum* s, MR_GLOBAL float* color_out,
                                 MR_GLOBAL float* luminance_out, MR_GLOBAL float* variance_out,
                                 int p) {
  // weight > 0: the centre's own weight is the kernel's, 9/64, times 1 up to rounding.
  const float inv = 1.0f / s->weight;
  color_out[3 * p] = s->r * inv;
  color_out[3 * p + 1] = s->g * inv;
  color_out[3 * p + 2] = s->b * inv;
  denoise_store_luminance(color_out, luminance_out, p);
  variance_out[p] = s->variance * inv * inv;
}

// One à-trous iteration at pixel (x, y) with taps `step` pixels apart: the 5x5 B3-spline
// taps that lie inside the image, each weighted by the guides and by how many standard
// deviations of noise its luminance differs from the centre's, normalised by the sum of
// the weights. Writes the filtered colour, its luminance (for the next iteration's taps)
// and the variance of the filtered value. `luminance_in`: of `color_in`
// (denoise_store_luminance); `guides`, `slopes`: denoise_pack_guides's.
MR_DEVICE void denoise_atrous_pixel(const MR_GLOBAL float* color_in,
                                    const MR_GLOBAL float* luminance_in,
                                    const MR_GLOBAL float* variance_in,
                                    const MR_GLOBAL float* guides, const MR_GLOBAL float* slopes,
                                    MR_GLOBAL float* color_out, MR_GLOBAL float* luminance_out,
                                    MR_GLOBAL float* variance_out, int width, int height, int x,
                                    int y, int step, const DenoiseWeights* w) {
  const int p = y * width + x, pixels = width * height;
  const DenoiseCentre centre = denoise_centre(guides, slopes, pixels, p, w);
  const float lp = luminance_in[p];
  const float inv_scale =
      denoise_luminance_scale(denoise_blurred_variance(variance_in, width, height, x, y), w);
  DenoiseSum s;
  s.weight = 0.0f, s.r = 0.0f, s.g = 0.0f, s.b = 0.0f, s.variance = 0.0f;
  for (int j = -2; j <= 2; ++j) {
    const int qy = y + j * step;
    if (qy < 0 || qy >= height) continue;
    for (int i = -2; i <= 2; ++i) {
      const int qx = x + i * step;
      if (qx < 0 || qx >= width) continue;
      const int q = qy * width + qx;
      float exponent;
      const float cosine = denoise_atrous_terms(&centre, lp, inv_scale, guides, luminance_in,
                                                pixels, q, i * step, j * step, &exponent);
      const float k = denoise_tap_weight(denoise_b3(i) * denoise_b3(j), cosine,
                                         denoise_normal_weight(cosine, w), exponent);
      denoise_sum_add(&s, k, color_in, variance_in, q);
    }
  }
  denoise_sum_store(&s, color_out, luminance_out, variance_out, p);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_ATROUS_H
