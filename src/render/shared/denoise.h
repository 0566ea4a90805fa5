// The denoiser's per-pixel steps, written once in render/shared/language.h's dialect: the
// CPU's driver (render/denoise.cpp) and the OpenCL program (device/opencl/kernels/
// denoise.cl) call the same functions over full-frame buffers, OpenCL pixel by pixel, the
// CPU mostly for several neighbouring pixels at once (render/denoise_rows.h).
//
// The filter is the edge-avoiding à-trous wavelet transform of Dammertz, Sewtz, Hanika and
// Lensch, "Edge-Avoiding À-Trous Wavelet Transform for fast Global Illumination
// Filtering" (HPG 2010): a 5x5 B3-spline kernel applied `iterations` times with taps
// 1, 2, 4, ... pixels apart, each tap weighted down where the guides (normal, depth,
// albedo) or the colour differ from the centre's (the normal's allowing for the turn of
// the centre's own surface, render/shared/denoise_normal.h). The colour weight is scaled
// by the standard deviation of the noise, as in Schied et al., "Spatiotemporal
// Variance-Guided Filtering" (HPG 2017), and the variance is filtered alongside the
// colour with the squared weights, so each iteration knows how much noise is left.
//
// Buffers (all row-major, `width` x `height`): colours 3 floats a pixel (linear RGB),
// normals 3 (unit, world space, 0 on a miss), depth 1 (along the camera axis, +inf on a
// miss), variances 1 (of a pixel's luminance). The filter works on the beauty minus its
// emission (render/shared/aov.h: emitters seen directly or through glass, when given)
// divided by denoise_factor (demodulated: the lighting without the texture), so texture
// detail is never blurred, and a light is neither spread over its neighbours nor shuts
// them out by its luminance; denoise_remodulate multiplies it back and adds the emission
// back unfiltered (emitters are seen sharp).
#ifndef MULTIRAY_RENDER_SHARED_DENOISE_H
#define MULTIRAY_RENDER_SHARED_DENOISE_H

#ifdef __cplusplus
#include "render/shared/denoise_normal.h"
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
// defaults); the OpenCL host passes the four sigmas as kernel arguments and both sides
// fill the struct with denoise_weights.
typedef struct {
  float sigma_luminance;  // colour: luminance difference in standard deviations of noise
  float sigma_normal;     // normal: exponent of the cosine of the angle between the
                          // normals beyond the turn the centre's surface predicts
                          // (denoise_normal_cosine)
  float sigma_depth;      // depth: relative error of the planar prediction of 1/depth
  float sigma_albedo;     // albedo: largest channel difference
  // sigma_normal as 2^k for k in 0..MR_DENOISE_MAX_SQUARINGS: k, the cosine's squarings
  // that raise it to sigma_normal (SVGF's 128: 7 multiplications instead of a pow);
  // otherwise -1 (pow).
  int normal_squarings;
  // 1: the normal term allows for the turn the centre's surface predicts (ours,
  // render/shared/denoise_normal.h); 0: the normals' cosine alone, as SVGF's and Dammertz
  // et al.'s normal term (the turns read as 0: that cosine to the bit).
  int normal_turn;
} DenoiseWeights;

#define MR_DENOISE_MAX_SQUARINGS 10

MR_DEVICE DenoiseWeights denoise_weights(float sigma_luminance, float sigma_normal,
                                         float sigma_depth, float sigma_albedo, int normal_turn) {
  DenoiseWeights w;
  w.sigma_luminance = sigma_luminance;
  w.sigma_normal = sigma_normal;
  w.sigma_depth = sigma_depth;
  w.sigma_albedo = sigma_albedo;
  w.normal_turn = normal_turn;
  w.normal_squarings = -1;
  float power = 1.0f;
  for (int k = 0; k <= MR_DENOISE_MAX_SQUARINGS; ++k, power *= 2.0f)
    if (sigma_normal == power) w.normal_squarings = k;
  return w;
}

// cosine^sigma_normal, the normals' weight: by repeated squaring when the exponent is a
// power of two (the same value as pow up to float rounding), else pow.
MR_DEVICE float denoise_normal_weight(float cosine, const DenoiseWeights* w) {
  float v = cosine;
  if (w->normal_squarings == 7) {  // the default, 128, unrolled
    v *= v;
    v *= v;
    v *= v;
    v *= v;
    v *= v;
    v *= v;
    return v * v;
  }
  if (w->normal_squarings < 0) return mr_pow(cosine, w->sigma_normal);
  for (int k = 0; k < w->normal_squarings; ++k) v *= v;
  return v;
}

// Below this exponent exp gives less than the smallest normal float (exp(-87.3365) is
// 2^-126), which the CPU filter's float mode flushes to 0 (render/denoise.cpp): a tap
// whose exponent is lower has weight 0 (denoise_tap_weight), and denoise_exp need not
// reach below it. (A device that keeps denormals loses a weight under 1.2e-38 of the
// centre's 9/64.)
#define MR_DENOISE_EXP_ZERO -87.34f

// exp(x) for the weights' exponents, x in [MR_DENOISE_EXP_ZERO, 0] (also right up to
// x = 88), by a polynomial rather than the library's exp: branch-free, so the CPU computes
// it for several neighbouring pixels at once (render/denoise_rows.cpp), and the same bits
// on every backend, being additions and multiplications only (correctly rounded in C++
// and OpenCL C alike; the OpenCL build contracts nothing into fma, and the CPU's code has
// no fma). x = n ln 2 + r with n an integer and |r| <= ln 2 / 2 (ln 2 in two parts, the
// first exact in few bits, so n times it is exact); exp(r) by the polynomial of Cephes'
// expf (S. L. Moshier, Cephes Math Library); 2^n written into the exponent's bits. Its
// relative error is a few float ulp (Denoise.PolynomialExpIsWithinAFewUlps). Below
// MR_DENOISE_EXP_ZERO, n + 127 leaves the exponent field: callers clamp x first.
MR_DEVICE float denoise_exp(float x) {
  const float shift = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
  const float t = x * 1.44269504f + shift;
  const float n = t - shift;  // x / ln 2 rounded to the nearest integer
  const float r = (x - n * 0.693359375f) + n * 2.12194440e-4f;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = p * (r * r) + r + 1.0f;
  // n sits in t's low mantissa bits: t's bits minus shift's are n (mod 2^32).
  const mr_uint biased = mr_float_as_uint(t) - mr_float_as_uint(shift) + 127u;
  return p * mr_uint_as_float(biased << 23);
}

MR_DEVICE float denoise_luminance(mr_float3 c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// The luminance of colour pixel `i` into `luminance_out`: each pass that writes a colour
// the filter reads writes its luminance too, so taps read it instead of computing it.
MR_DEVICE void denoise_store_luminance(const MR_GLOBAL float* color,
                                       MR_GLOBAL float* luminance_out, int i) {
  luminance_out[i] = denoise_luminance(load3(color + 3 * i));
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

// Channel `k` of pixel `i`'s emission, the part of the beauty left unfiltered: 0 without
// an emission buffer (`has_emission` 0; `emission` may then be null in C++, the OpenCL
// host binds a placeholder) and where it is not finite.
MR_DEVICE float denoise_emission(const MR_GLOBAL float* emission, int has_emission, int i, int k) {
  float e = 0.0f;
  if (has_emission) e = emission[3 * i + k];  // branched: the placeholder is never read
  return mr_isfinite(e) ? e : 0.0f;
}

// Channel `k` of what pixel `i` filters, before demodulation: the beauty (0 where not
// finite: one NaN would otherwise spread over the filter's whole footprint) minus the
// emission, at least 0 (the emission never exceeds the beauty but by rounding).
MR_DEVICE float denoise_unemitted(const MR_GLOBAL float* beauty, const MR_GLOBAL float* emission,
                                  int has_emission, int i, int k) {
  const float c = beauty[3 * i + k];
  const float rest = (mr_isfinite(c) ? c : 0.0f) - denoise_emission(emission, has_emission, i, k);
  return rest > 0.0f ? rest : 0.0f;
}

// Pixel `i` demodulated into `color_out` (and its luminance into `luminance_out`): the
// beauty minus the emission (denoise_unemitted) divided by denoise_factor. With
// `variance` (may be null in C++; the OpenCL host passes has_variance 0 instead) the given
// variance is scaled to the demodulated colour, by the factor's luminance squared (exact
// for a grey albedo, an approximation for a coloured one).
MR_DEVICE void denoise_demodulate(const MR_GLOBAL float* beauty, const MR_GLOBAL float* emission,
                                  int has_emission, const MR_GLOBAL float* albedo,
                                  const MR_GLOBAL float* depth, const MR_GLOBAL float* variance,
                                  int has_variance, MR_GLOBAL float* color_out,
                                  MR_GLOBAL float* luminance_out, MR_GLOBAL float* variance_out,
                                  int i) {
  const mr_float3 f = denoise_factor(albedo, depth, i);
  // Channel by channel: clang turns finite3's && into a select guarded by an LLVM
  // `freeze`, which Oclgrind's --uninitialized check cannot interpret.
  color_out[3 * i] = denoise_unemitted(beauty, emission, has_emission, i, 0) / f.x;
  color_out[3 * i + 1] = denoise_unemitted(beauty, emission, has_emission, i, 1) / f.y;
  color_out[3 * i + 2] = denoise_unemitted(beauty, emission, has_emission, i, 2) / f.z;
  denoise_store_luminance(color_out, luminance_out, i);
  if (has_variance) {
    const float l = denoise_luminance(f);
    const float v = variance[i];
    variance_out[i] = mr_isfinite(v) && v > 0.0f ? v / (l * l) : 0.0f;
  }
}

// The demodulated pixel `i` multiplied back by its factor, plus its emission
// (denoise_emission), into `out`.
MR_DEVICE void denoise_remodulate(const MR_GLOBAL float* color, const MR_GLOBAL float* emission,
                                  int has_emission, const MR_GLOBAL float* albedo,
                                  const MR_GLOBAL float* depth, MR_GLOBAL float* out, int i) {
  const mr_float3 f = denoise_factor(albedo, depth, i);
  out[3 * i] = color[3 * i] * f.x + denoise_emission(emission, has_emission, i, 0);
  out[3 * i + 1] = color[3 * i + 1] * f.y + denoise_emission(emission, has_emission, i, 1);
  out[3 * i + 2] = color[3 * i + 2] * f.z + denoise_emission(emission, has_emission, i, 2);
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

// The guides packed for the filter's taps, MR_DENOISE_GUIDE_FLOATS floats a pixel, so that
// a tap reads one place instead of three buffers and divides nothing: normal (3), 1/depth
// (denoise_inv_depth), albedo (3), and 1 on a miss, 0 on a hit. They are planes, one
// float a pixel each (float k of pixel i at guides[k * pixels + i]), so the guides of
// neighbouring pixels are neighbours in memory: the CPU filters several pixels of a row
// at once (render/denoise_rows.cpp).
#define MR_DENOISE_GUIDE_FLOATS 8
// The slopes, planes likewise, MR_DENOISE_SLOPE_FLOATS floats a pixel (float k of pixel i
// at slopes[k * pixels + i]): the slopes of 1/depth along x and y (denoise_slope), then
// the normal's turns per pixel along x and y (denoise_normal_turn).
#define MR_DENOISE_SLOPE_FLOATS 4

// Writes pixel (x, y)'s guides and its slopes: what every iteration of the filter reads,
// made once a frame.
MR_DEVICE void denoise_pack_guides(const MR_GLOBAL float* albedo, const MR_GLOBAL float* normal,
                                   const MR_GLOBAL float* depth, int width, int height, int x,
                                   int y, MR_GLOBAL float* guides_out,
                                   MR_GLOBAL float* slopes_out) {
  const int i = y * width + x, pixels = width * height;
  MR_GLOBAL float* g = guides_out + i;
  g[0] = normal[3 * i];
  g[pixels] = normal[3 * i + 1];
  g[2 * pixels] = normal[3 * i + 2];
  g[3 * pixels] = denoise_inv_depth(depth, i);
  g[4 * pixels] = albedo[3 * i];
  g[5 * pixels] = albedo[3 * i + 1];
  g[6 * pixels] = albedo[3 * i + 2];
  g[7 * pixels] = denoise_is_miss(depth, i) ? 1.0f : 0.0f;
  const int left = x > 0, right = x + 1 < width, up = y > 0, down = y + 1 < height;
  MR_GLOBAL float* s = slopes_out + i;
  s[0] = denoise_slope(depth, i, 1, left, right);
  s[pixels] = denoise_slope(depth, i, width, up, down);
  s[2 * pixels] = denoise_normal_turn(normal, depth, i, 1, left, right);
  s[3 * pixels] = denoise_normal_turn(normal, depth, i, width, up, down);
}

// Pixel p's side of the guide weights of its taps, loaded once for all of them: its
// guides, its slopes and turns, and the depth and albedo terms' divisors as reciprocals.
typedef struct {
  mr_float3 normal, albedo;
  float inv_depth, slope_x, slope_y;
  float turn_x, turn_y;  // the normal's per pixel (denoise_normal_turn)
  float depth_scale;     // 1 / (p's 1/depth * sigma_depth); 0 on a miss (unused)
  float albedo_scale;    // 1 / sigma_albedo
  int miss;
} DenoiseCentre;

// `pixels`: the frame's, width * height (the planes' size).
MR_DEVICE DenoiseCentre denoise_centre(const MR_GLOBAL float* guides,
                                       const MR_GLOBAL float* slopes, int pixels, int p,
                                       const DenoiseWeights* w) {
  const MR_GLOBAL float* g = guides + p;
  DenoiseCentre c;
  c.normal = MR_FLOAT3(g[0], g[pixels], g[2 * pixels]);
  c.albedo = MR_FLOAT3(g[4 * pixels], g[5 * pixels], g[6 * pixels]);
  c.inv_depth = g[3 * pixels];
  c.slope_x = slopes[p];
  c.slope_y = slopes[pixels + p];
  c.turn_x = w->normal_turn ? slopes[2 * pixels + p] : 0.0f;
  c.turn_y = w->normal_turn ? slopes[3 * pixels + p] : 0.0f;
  c.miss = g[7 * pixels] != 0.0f;
  // Selected, not branched (denoise_guide_terms): a miss's 1/depth is 0, its scale inf.
  const float depth_scale = 1.0f / (c.inv_depth * w->sigma_depth);
  c.depth_scale = c.miss ? 0.0f : depth_scale;
  c.albedo_scale = 1.0f / w->sigma_albedo;
  return c;
}

// The guides' terms of tap q's weight when filtering the centre c: returns the cosine
// between the normals beyond the turn c's surface predicts (denoise_normal_cosine),
// which denoise_normal_weight raises to the normal's weight, and
// sets *exponent to the sum of the depth's and albedo's exponents (the weight is then
// the normal's weight times exp(*exponent), denoise_tap_weight). Misses mix only with
// misses: cosine 1 and exponent 0 (weight exactly 1) when both are misses, cosine 0 (no
// weight) when one is. A caller with exponents of its own adds them before one exp
// (denoise_atrous_terms). (dx, dy): q - p in pixels. Branch-free (every term computed,
// the answer selected), so that the CPU can compute neighbouring pixels together
// (render/denoise_rows.cpp): what a pixel gets does not depend on its neighbours.
MR_DEVICE float denoise_guide_terms(const DenoiseCentre* c, const MR_GLOBAL float* guides,
                                    int pixels, int q, int dx, int dy, float* exponent) {
  const MR_GLOBAL float* g = guides + q;
  const int miss_q = g[7 * pixels] != 0.0f;
  const float cosine = dot3(c->normal, MR_FLOAT3(g[0], g[pixels], g[2 * pixels]));
  // How far q's 1/depth lies off p's plane, relative to p's 1/depth.
  const float predicted = c->inv_depth + c->slope_x * (float)dx + c->slope_y * (float)dy;
  const float off = mr_fabs(g[3 * pixels] - predicted) * c->depth_scale;
  const mr_float3 da = c->albedo - MR_FLOAT3(g[4 * pixels], g[5 * pixels], g[6 * pixels]);
  const float a = mr_fmax(mr_fabs(da.x), mr_fmax(mr_fabs(da.y), mr_fabs(da.z))) * c->albedo_scale;
  // | and & on ints, not || and &&: clang turns those into selects guarded by an LLVM
  // `freeze`, which Oclgrind's --uninitialized check cannot interpret.
  // Selects one after the other, not nested: see denoise_tap_weight.
  const int any_miss = c->miss | miss_q;
  const float misses = (c->miss & miss_q) ? 1.0f : 0.0f;
  *exponent = any_miss ? 0.0f : -(off * off) - a * a;
  const float normal_cosine = denoise_normal_cosine(cosine, c->turn_x, c->turn_y, dx, dy);
  return any_miss ? misses : normal_cosine;
}

// A tap's weight: `kernel_weight` (the filter's own weight of the tap) times the normals'
// weight `normal_weight` (denoise_normal_weight of `cosine`) times exp(`exponent`); 0
// where the cosine is not positive (the normals face apart, or a miss meets a hit) or the
// exponent is below MR_DENOISE_EXP_ZERO. Selected, not branched (see
// denoise_guide_terms). (Not `kernel`: a keyword of OpenCL C.)
MR_DEVICE float denoise_tap_weight(float kernel_weight, float cosine, float normal_weight,
                                   float exponent) {
  // Selects one after the other, on values: GCC vectorises these across pixels, not
  // nested conditions, nor mr_fmax (C++'s std::max returns a reference, and GCC then
  // loads from a selected address).
  const float e = cosine > 0.0f ? exponent : -INFINITY;
  const float clamped = e < MR_DENOISE_EXP_ZERO ? MR_DENOISE_EXP_ZERO : e;
  const float k = kernel_weight * normal_weight * denoise_exp(clamped);
  return e >= MR_DENOISE_EXP_ZERO ? k : 0.0f;
}

// The guides' weight of tap q for the centre c (denoise_guide_terms, the normal's weight
// and exp taken).
MR_DEVICE float denoise_guide_weight(const DenoiseCentre* c, const MR_GLOBAL float* guides,
                                     int pixels, int q, int dx, int dy, const DenoiseWeights* w) {
  float exponent;
  const float cosine = denoise_guide_terms(c, guides, pixels, q, dx, dy, &exponent);
  return denoise_tap_weight(1.0f, cosine, denoise_normal_weight(cosine, w), exponent);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_H
