// The denoiser's per-pixel steps, written once in render/shared/language.h's dialect: the
// CPU's driver (render/denoise.cpp) and the OpenCL program (device/opencl/kernels/
// denoise.cl) call the same functions, pixel by pixel, over full-frame buffers.
//
// The filter is the edge-avoiding à-trous wavelet transform of Dammertz, Sewtz, Hanika and
// Lensch, "Edge-Avoiding À-Trous Wavelet Transform for fast Global Illumination
// Filtering" (HPG 2010): a 5x5 B3-spline kernel applied `iterations` times with taps
// 1, 2, 4, ... pixels apart, each tap weighted down where the guides (normal, depth,
// albedo) or the colour differ from the centre's. The colour weight is scaled by the
// standard deviation of the noise, as in Schied et al., "Spatiotemporal Variance-Guided
// Filtering" (HPG 2017), and the variance is filtered alongside the colour with the
// squared weights, so each iteration knows how much noise is left.
//
// Buffers (all row-major, `width` x `height`): colours 3 floats a pixel (linear RGB),
// normals 3 (unit, world space, 0 on a miss), depth 1 (along the camera axis, +inf on a
// miss), variances 1 (of a pixel's luminance). The filter works on the beauty divided by
// denoise_factor (demodulated: the lighting without the texture), so texture detail is
// never blurred; denoise_remodulate multiplies it back.
#ifndef MULTIRAY_RENDER_SHARED_DENOISE_H
#define MULTIRAY_RENDER_SHARED_DENOISE_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// What albedo is raised by before dividing: a black surface's colour is then multiplied
// by 100, not divided by 0, and multiplying back gives the beauty exactly where it is 0.
#define MR_DENOISE_ALBEDO_EPS 0.01f
// Half the side of the window the variance is estimated in when no variance is given
// (7x7, as SVGF's spatial estimate for pixels with a short history).
#define MR_DENOISE_VARIANCE_RADIUS 3

// The edge-stopping parameters of one filter run (render/denoise.h documents the
// defaults); plain floats, so the OpenCL host passes them as kernel arguments.
typedef struct {
  float sigma_luminance;  // colour: luminance difference in standard deviations of noise
  float sigma_normal;     // normal: exponent of the cosine between the normals
  float sigma_depth;      // depth: relative error of the planar prediction of 1/depth
  float sigma_albedo;     // albedo: largest channel difference
} DenoiseWeights;

MR_DEVICE float denoise_luminance(mr_float3 c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// B3-spline taps (1, 4, 6, 4, 1) / 16 at offsets -2..2.
MR_DEVICE float denoise_b3(int k) {
  // Compared, not abs(k): clang turns that into llvm.abs, which Oclgrind cannot run.
  return k == 0 ? 0.375f : (k == 1 || k == -1 ? 0.25f : 0.0625f);
}

MR_DEVICE bool denoise_is_miss(const MR_GLOBAL float* depth, int i) {
  return !(depth[i] < INFINITY);
}

// What pixel `i`'s beauty is divided by before filtering and multiplied by after:
// albedo + MR_DENOISE_ALBEDO_EPS per channel. On a miss (the environment seen directly,
// which has no albedo) and where the albedo is not finite: 1, no demodulation.
MR_DEVICE mr_float3 denoise_factor(const MR_GLOBAL float* albedo, const MR_GLOBAL float* depth,
                                   int i) {
  const mr_float3 a = load3(albedo + 3 * i);
  if (denoise_is_miss(depth, i) || !finite3(a)) return MR_FLOAT3(1.0f, 1.0f, 1.0f);
  return MR_FLOAT3(mr_fmax(a.x, 0.0f), mr_fmax(a.y, 0.0f), mr_fmax(a.z, 0.0f)) +
         MR_FLOAT3(MR_DENOISE_ALBEDO_EPS, MR_DENOISE_ALBEDO_EPS, MR_DENOISE_ALBEDO_EPS);
}

// Pixel `i` demodulated into `color_out`; a non-finite beauty channel is taken as 0 (one
// NaN would otherwise spread over the filter's whole footprint). With `variance` (may be
// null in C++; the OpenCL host passes has_variance 0 instead) the given variance is
// scaled to the demodulated colour, by the factor's luminance squared (exact for a grey
// albedo, an approximation for a coloured one).
MR_DEVICE void denoise_demodulate(const MR_GLOBAL float* beauty, const MR_GLOBAL float* albedo,
                                  const MR_GLOBAL float* depth, const MR_GLOBAL float* variance,
                                  int has_variance, MR_GLOBAL float* color_out,
                                  MR_GLOBAL float* variance_out, int i) {
  const mr_float3 f = denoise_factor(albedo, depth, i);
  const mr_float3 c = load3(beauty + 3 * i);
  // Channel by channel: clang turns finite3's && into a select guarded by an LLVM
  // `freeze`, which Oclgrind's --uninitialized check cannot interpret.
  color_out[3 * i] = (mr_isfinite(c.x) ? c.x : 0.0f) / f.x;
  color_out[3 * i + 1] = (mr_isfinite(c.y) ? c.y : 0.0f) / f.y;
  color_out[3 * i + 2] = (mr_isfinite(c.z) ? c.z : 0.0f) / f.z;
  if (has_variance) {
    const float l = denoise_luminance(f);
    const float v = variance[i];
    variance_out[i] = mr_isfinite(v) && v > 0.0f ? v / (l * l) : 0.0f;
  }
}

// The demodulated pixel `i` multiplied back by its factor into `out`.
MR_DEVICE void denoise_remodulate(const MR_GLOBAL float* color, const MR_GLOBAL float* albedo,
                                  const MR_GLOBAL float* depth, MR_GLOBAL float* out, int i) {
  const mr_float3 f = denoise_factor(albedo, depth, i);
  out[3 * i] = color[3 * i] * f.x;
  out[3 * i + 1] = color[3 * i + 1] * f.y;
  out[3 * i + 2] = color[3 * i + 2] * f.z;
}

// 1 / depth (0 on a miss: a miss is a surface at infinity).
MR_DEVICE float denoise_inv_depth(const MR_GLOBAL float* depth, int i) {
  return denoise_is_miss(depth, i) ? 0.0f : 1.0f / depth[i];
}

// The change of 1/depth per pixel along one axis at pixel `i`: of the differences to the
// neighbours before (`i - stride`) and after (`i + stride`), where they exist and are hits,
// the smaller one, so that a depth edge beside the pixel does not tilt its plane. 1/depth
// is affine in screen space on a plane, so the slope predicts the plane exactly.
MR_DEVICE float denoise_slope(const MR_GLOBAL float* depth, int i, int stride, int has_before,
                              int has_after) {
  const float z = denoise_inv_depth(depth, i);
  const int before = has_before && !denoise_is_miss(depth, i - stride);
  const int after = has_after && !denoise_is_miss(depth, i + stride);
  const float db = before ? z - denoise_inv_depth(depth, i - stride) : 0.0f;
  const float da = after ? denoise_inv_depth(depth, i + stride) - z : 0.0f;
  if (before && after) return mr_fabs(db) < mr_fabs(da) ? db : da;
  return before ? db : da;
}

// The weight the guides give tap q when filtering pixel p, as factor · exp(*exponent): 0
// or 1 (exponent 0) when one or both are misses (misses mix only with misses); otherwise
// the normal's weight times exp of the depth's and albedo's exponents. A caller with more
// exponents of its own adds them before one exp (denoise_atrous_pixel). (dx, dy): q - p in
// pixels; (sx, sy): p's slopes of 1/depth.
MR_DEVICE float denoise_guide_terms(const MR_GLOBAL float* albedo, const MR_GLOBAL float* normal,
                                    const MR_GLOBAL float* depth, int p, int q, int dx, int dy,
                                    float sx, float sy, const DenoiseWeights* w, float* exponent) {
  *exponent = 0.0f;
  const bool miss_p = denoise_is_miss(depth, p), miss_q = denoise_is_miss(depth, q);
  if (miss_p || miss_q) return miss_p && miss_q ? 1.0f : 0.0f;
  const float cosine = mr_fmax(0.0f, dot3(load3(normal + 3 * p), load3(normal + 3 * q)));
  if (!(cosine > 0.0f)) return 0.0f;
  const float w_normal = mr_pow(cosine, w->sigma_normal);
  // How far q's 1/depth lies off p's plane, relative to p's 1/depth.
  const float zp = denoise_inv_depth(depth, p);
  const float predicted = zp + sx * (float)dx + sy * (float)dy;
  const float off = mr_fabs(denoise_inv_depth(depth, q) - predicted) / (zp * w->sigma_depth);
  const mr_float3 da = load3(albedo + 3 * p) - load3(albedo + 3 * q);
  const float a = mr_fmax(mr_fabs(da.x), mr_fmax(mr_fabs(da.y), mr_fabs(da.z))) / w->sigma_albedo;
  *exponent = -(off * off) - a * a;
  return w_normal;
}

// The guides' weight of tap q for pixel p (denoise_guide_terms, exp taken).
MR_DEVICE float denoise_guide_weight(const MR_GLOBAL float* albedo, const MR_GLOBAL float* normal,
                                     const MR_GLOBAL float* depth, int p, int q, int dx, int dy,
                                     float sx, float sy, const DenoiseWeights* w) {
  float exponent;
  const float factor =
      denoise_guide_terms(albedo, normal, depth, p, q, dx, dy, sx, sy, w, &exponent);
  return factor > 0.0f ? factor * mr_exp(exponent) : 0.0f;
}

// p's slopes of 1/depth, x and y (denoise_slope).
MR_DEVICE mr_float2 denoise_slopes(const MR_GLOBAL float* depth, int width, int height, int x,
                                   int y) {
  const int p = y * width + x;
  return MR_FLOAT2(denoise_slope(depth, p, 1, x > 0, x + 1 < width),
                   denoise_slope(depth, p, width, y > 0, y + 1 < height));
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_H
