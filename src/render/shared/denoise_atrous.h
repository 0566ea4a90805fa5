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
  const DenoiseCentre centre = denoise_centre(guides, slopes, y * width + x, w);
  float sum = 0.0f, m1 = 0.0f, m2 = 0.0f;
  for (int dy = -MR_DENOISE_VARIANCE_RADIUS; dy <= MR_DENOISE_VARIANCE_RADIUS; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -MR_DENOISE_VARIANCE_RADIUS; dx <= MR_DENOISE_VARIANCE_RADIUS; ++dx) {
      const int qx = x + dx;
      if (qx < 0 || qx >= width) continue;
      const int q = qy * width + qx;
      const float g = denoise_guide_weight(&centre, guides, q, dx, dy, w);
      const float l = luminance[q];
      sum += g;
      m1 += g * l;
      m2 += g * l * l;
    }
  }
  // sum >= the centre's own weight, which is 1 up to rounding.
  m1 /= sum;
  m2 /= sum;
  return mr_fmax(0.0f, m2 - m1 * m1);
}

// The variance the filter starts from at pixel (x, y): the renderer's (`given`, scaled by
// denoise_demodulate) where it was given, else the spatial estimate above. Also the
// spatial estimate for a black pixel whose given variance is 0: all its samples returned
// nothing, which says little about its mean at a few samples per pixel, yet a variance of
// 0 makes the luminance weight shut out every neighbour, so the pixel stayed black
// (issue 52: the salt and pepper of the Sponza hall at 16 spp). Among black neighbours
// the estimate is 0 too: a region that is black throughout stays black.
MR_DEVICE float denoise_start_variance(int has_variance, const MR_GLOBAL float* given,
                                       const MR_GLOBAL float* luminance,
                                       const MR_GLOBAL float* guides,
                                       const MR_GLOBAL float* slopes, int width, int height, int x,
                                       int y, const DenoiseWeights* w) {
  const int i = y * width + x;
  if (has_variance && !(given[i] == 0.0f && luminance[i] == 0.0f)) return given[i];
  return denoise_spatial_variance(luminance, guides, slopes, width, height, x, y, w);
}

// The variance at p blurred by a 3x3 Gaussian (1 2 1 / 2 4 2 / 1 2 1, over what lies
// inside the image): SVGF's guard against a noisy variance estimate stopping the filter.
MR_DEVICE float denoise_blurred_variance(const MR_GLOBAL float* variance, int width, int height,
                                         int x, int y) {
  float sum = 0.0f, total = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qx >= width || qy < 0 || qy >= height) continue;
      const float k = (dx == 0 ? 2.0f : 1.0f) * (dy == 0 ? 2.0f : 1.0f);
      sum += k * variance[qy * width + qx];
      total += k;
    }
  return sum / total;
}

// One à-trous iteration at pixel (x, y) with taps `step` pixels apart: the 5x5 B3-spline
// taps that lie inside the image, each weighted by the guides and by how many standard
// deviations of noise its luminance differs from the centre's, normalised by the sum of
// the weights. Writes the filtered colour, its luminance (for the next iteration's taps)
// and the variance of the filtered value (the variances of the taps with the squared
// weights, the taps taken as independent). `luminance_in`: of `color_in`
// (denoise_store_luminance); `guides`, `slopes`: denoise_pack_guides's.
MR_DEVICE void denoise_atrous_pixel(const MR_GLOBAL float* color_in,
                                    const MR_GLOBAL float* luminance_in,
                                    const MR_GLOBAL float* variance_in,
                                    const MR_GLOBAL float* guides, const MR_GLOBAL float* slopes,
                                    MR_GLOBAL float* color_out, MR_GLOBAL float* luminance_out,
                                    MR_GLOBAL float* variance_out, int width, int height, int x,
                                    int y, int step, const DenoiseWeights* w) {
  const int p = y * width + x;
  const DenoiseCentre centre = denoise_centre(guides, slopes, p, w);
  const float lp = luminance_in[p];
  // 1e-10: a noiseless image (variance 0) still divides by something, and its equal
  // luminances give weight exp(0) = 1. Its reciprocal, to multiply each tap by.
  const float inv_scale =
      1.0f /
      (w->sigma_luminance * mr_sqrt(denoise_blurred_variance(variance_in, width, height, x, y)) +
       1e-10f);
  float sum = 0.0f, var = 0.0f;
  mr_float3 c = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  for (int j = -2; j <= 2; ++j) {
    const int qy = y + j * step;
    if (qy < 0 || qy >= height) continue;
    for (int i = -2; i <= 2; ++i) {
      const int qx = x + i * step;
      if (qx < 0 || qx >= width) continue;
      const int q = qy * width + qx;
      float exponent;
      const float cosine = denoise_guide_terms(&centre, guides, q, i * step, j * step, &exponent);
      if (!(cosine > 0.0f)) continue;  // weight 0: the tap adds nothing
      // One exp for the guides' and the luminance's exponents together.
      exponent -= mr_fabs(luminance_in[q] - lp) * inv_scale;
      if (exponent < MR_DENOISE_EXP_ZERO) continue;  // weight 0 too
      const float k =
          denoise_b3(i) * denoise_b3(j) * denoise_normal_weight(cosine, w) * mr_exp(exponent);
      sum += k;
      c = c + load3(color_in + 3 * q) * k;
      var += k * k * variance_in[q];
    }
  }
  // sum > 0: the centre's own weight is the kernel's, 9/64, times 1 up to rounding.
  const float inv = 1.0f / sum;
  color_out[3 * p] = c.x * inv;
  color_out[3 * p + 1] = c.y * inv;
  color_out[3 * p + 2] = c.z * inv;
  denoise_store_luminance(color_out, luminance_out, p);
  variance_out[p] = var * inv * inv;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_ATROUS_H
