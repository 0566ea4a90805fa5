// The environment map's geometry and importance sampling, written once for every backend
// (the environment light of render/shared/sky.h), in render/shared/language.h's dialect. The map
// is equirectangular in the frame (x, up, z) of render/environment.h's EnvFrame: u right, v down,
// both in [0, 1]; its middle column (u = 1/2) looks along -z, u = 3/4 along +x.
#ifndef MULTIRAY_RENDER_SHARED_ENVIRONMENT_H
#define MULTIRAY_RENDER_SHARED_ENVIRONMENT_H

#ifdef __cplusplus
#include "render/shared/language.h"
#include "render/shared/sampling.h"
#endif

MR_NAMESPACE_BEGIN

// Map coordinates of unit direction `d`.
MR_DEVICE mr_float2 equirect_uv(mr_float3 x, mr_float3 up, mr_float3 z, mr_float3 d) {
  const float lx = dot3(d, x), ly = dot3(d, up), lz = dot3(d, z);
  const float phi = mr_atan2(lx, -lz);  // 0 along -z, pi/2 along +x
  const float theta = mr_acos(mr_clamp(ly, -1.0f, 1.0f));
  return MR_FLOAT2(0.5f + phi * (0.5f * MR_INV_PI), theta * MR_INV_PI);
}

// The unit direction at map coordinates `uv` (equirect_uv's inverse).
MR_DEVICE mr_float3 equirect_direction(mr_float3 x, mr_float3 up, mr_float3 z, mr_float2 uv) {
  const float phi = (uv.x - 0.5f) * 2.0f * MR_PI, theta = uv.y * MR_PI;
  const float st = mr_sin(theta);
  return x * (st * mr_sin(phi)) + up * mr_cos(theta) - z * (st * mr_cos(phi));
}

// The column (or row) of a map `n` pixels wide (or high) that holds coordinate `u`.
MR_DEVICE mr_int equirect_texel(float u, mr_int n) {
  return mr_clamp((mr_int)(u * (float)n), 0, n - 1);
}

// Solid-angle density of the map's distribution at height `v`, whose pixel has
// probability `p_row` x `p_in_row` among the w x h: that times the pixel count over the
// Jacobian of the equirectangular map (2 pi^2 sin theta); 0 at the poles.
MR_DEVICE float equirect_pdf(float p_row, float p_in_row, mr_int w, mr_int h, float v) {
  const float st = mr_sin(v * MR_PI);
  if (!(st > 0.0f)) return 0.0f;
  const float p = p_row * p_in_row * (float)w * (float)h;
  return p / (2.0f * MR_PI * MR_PI * st);
}

// Map coordinates drawn from the piecewise-constant distribution of the w x h map whose
// rows have the cumulative table `row_cdf` (h entries, last = 1) and whose pixels have,
// per row, `col_cdf` (w x h, each row's last = 1): u1 picks the row, u2 the pixel, and
// what is left of each places the point inside the pixel.
MR_DEVICE mr_float2 sample_equirect(const MR_GLOBAL float* row_cdf, const MR_GLOBAL float* col_cdf,
                                    mr_uint w, mr_uint h, float u1, float u2) {
  const mr_uint y = pick_cdf(row_cdf, h, u1);
  const MR_GLOBAL float* row = col_cdf + y * w;
  const mr_uint x = pick_cdf(row, w, u2);
  // Where inside the pixel: the part of u2 (and u1) past the chosen bin's start.
  const float r0 = y == 0 ? 0.0f : row_cdf[y - 1], c0 = x == 0 ? 0.0f : row[x - 1];
  const float fy = mr_clamp((u1 - r0) / mr_fmax(row_cdf[y] - r0, 1e-20f), 0.0f, 1.0f);
  const float fx = mr_clamp((u2 - c0) / mr_fmax(row[x] - c0, 1e-20f), 0.0f, 1.0f);
  return MR_FLOAT2(((float)x + fx) / (float)w, ((float)y + fy) / (float)h);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_ENVIRONMENT_H
