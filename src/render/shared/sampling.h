// Warping functions from [0,1)^2 to directions and points, with their densities, the
// inversion of a tabulated discrete distribution and the clamp of a camera sample's
// radiance: one definition for the CPU's kernels and the OpenCL path tracer. Written in
// render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_SAMPLING_H
#define MULTIRAY_RENDER_SHARED_SAMPLING_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// (cos, sin) of the angle 2 pi `turns`, for `turns` in [0, 1] (a sample's azimuth): the
// nearest quarter turn is taken off exactly (4 x turns is exact), and the rest, within
// +-pi/4, goes through Taylor polynomials whose first omitted terms are at most 2.5e-8
// (cosine) and 2e-9 (sine), so both stay within a few float ulps of the true values.
// Plain arithmetic: the CPU and every OpenCL driver evaluate the same expression, without
// the library call that took 5% of a path-traced frame (libm's sincosf, reducing an
// argument of any size).
MR_DEVICE mr_float2 cos_sin_turns(float turns) {
  const float t = 4.0f * turns;
  const mr_int quarter = (mr_int)(t + 0.5f);  // the nearest quarter turn (t >= 0)
  const float a = (t - (float)quarter) * (0.5f * MR_PI), a2 = a * a;
  const float s =
      a * (1.0f + a2 * (-1.0f / 6.0f +
                        a2 * (1.0f / 120.0f + a2 * (-1.0f / 5040.0f + a2 * (1.0f / 362880.0f)))));
  const float c =
      1.0f + a2 * (-0.5f + a2 * (1.0f / 24.0f + a2 * (-1.0f / 720.0f + a2 * (1.0f / 40320.0f))));
  // Rotate by the quarter turns taken off: quarter 1 gives (-s, c), 2 (-c, -s), 3 (s, -c).
  // Selects and signs rather than a branch, which random azimuths would mispredict.
  const mr_int odd = quarter & 1;
  const float x = odd ? s : c, y = odd ? c : s;
  return MR_FLOAT2(x * (float)(1 - ((quarter + 1) & 2)), y * (float)(1 - (quarter & 2)));
}

// Cosine-weighted direction about +z (local frame); pdf = cos(theta) / pi.
MR_DEVICE mr_float3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = mr_sqrt(u1);
  const mr_float2 cs = cos_sin_turns(u2);
  return MR_FLOAT3(r * cs.x, r * cs.y, mr_sqrt(mr_fmax(0.0f, 1.0f - u1)));
}

// Uniform direction in the cone of directions within acos(cos_max) of +z (local frame).
MR_DEVICE mr_float3 sample_cone(float cos_max, float u1, float u2) {
  const float cos_t = 1.0f - u1 * (1.0f - cos_max);
  const float sin_t = mr_sqrt(mr_fmax(0.0f, 1.0f - cos_t * cos_t));
  const mr_float2 cs = cos_sin_turns(u2);
  return MR_FLOAT3(sin_t * cs.x, sin_t * cs.y, cos_t);
}

// sample_cone's density per solid angle.
MR_DEVICE float cone_pdf(float cos_max) { return 1.0f / (2.0f * MR_PI * (1.0f - cos_max)); }

// Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2
// (Heitz 2019, "A Low-Distortion Map Between Triangle and Square").
MR_DEVICE mr_float2 sample_triangle(float u1, float u2) {
  float b0, b1;
  if (u2 > u1) {
    b0 = u1 * 0.5f;
    b1 = u2 - b0;
  } else {
    b1 = u2 * 0.5f;
    b0 = u1 - b1;
  }
  return MR_FLOAT2(b1, 1.0f - b0 - b1);
}

// The point at barycentrics `bc` (of vertices b and c, as sample_triangle's) of triangle abc.
MR_DEVICE mr_float3 triangle_point(mr_float3 a, mr_float3 b, mr_float3 c, mr_float2 bc) {
  return a * (1.0f - bc.x - bc.y) + b * bc.x + c * bc.y;
}

// Index of the first entry of cdf[0, n) greater than `u`, the last if none (as
// std::upper_bound): draws from the discrete distribution whose cumulative table (non-
// decreasing, last entry 1) is `cdf`. n > 0.
MR_DEVICE mr_uint pick_cdf(const MR_GLOBAL float* cdf, mr_uint n, float u) {
  mr_uint lo = 0, hi = n;
  while (lo < hi) {
    const mr_uint mid = lo + (hi - lo) / 2;
    if (u < cdf[mid]) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return lo < n - 1 ? lo : n - 1;
}

// Russian roulette's probability that a path whose throughput's largest component is
// `beta_max` goes on: its square root, at most 1 (as Cycles does). The throughput alone
// (pbrt's rule) ends dim but useful paths early: after three bounces off surfaces of
// albedo 0.5 it kills 7 paths in 8, and what the survivors carry, 8 times brighter, is
// noise; the square root keeps 35% of them (Sponza in daylight, roulette from the third
// bounce: variance 16% lower for 10% more time; docs/benchmarks.md "Equal noise against
// Cycles"). RenderSettings::rr_start says from which bounce it plays.
MR_DEVICE float rr_survival(float beta_max) { return beta_max >= 1.0f ? 1.0f : mr_sqrt(beta_max); }

// Veach's power heuristic (beta = 2) for two strategies.
MR_DEVICE float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// --clamp: one camera sample's radiance (the path's whole contribution, finite and
// non-negative) scaled by limit / max component when that component exceeds `limit`, so
// the sample keeps its hue; limit 0 (off) or a sample within it returns `L` unchanged, bit
// for bit. Trades a bias (energy lost from the brightest paths, mostly caustics and small
// bright emitters seen indirectly) for bounded fireflies; docs/noise.md has the figures.
MR_DEVICE mr_float3 clamp_sample(mr_float3 L, float limit) {
  const float m = mr_fmax(L.x, mr_fmax(L.y, L.z));
  return limit > 0.0f && m > limit ? L * (limit / m) : L;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SAMPLING_H
