// Warping functions from [0,1)^2 to directions and points, with their densities: one
// definition for the CPU's kernels and the OpenCL path tracer. Written in
// render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_SAMPLING_H
#define MULTIRAY_RENDER_SHARED_SAMPLING_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// Cosine-weighted direction about +z (local frame); pdf = cos(theta) / pi.
MR_DEVICE mr_float3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = mr_sqrt(u1), phi = 2.0f * MR_PI * u2;
  return MR_FLOAT3(r * mr_cos(phi), r * mr_sin(phi), mr_sqrt(mr_fmax(0.0f, 1.0f - u1)));
}

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

// Veach's power heuristic (beta = 2) for two strategies.
MR_DEVICE float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SAMPLING_H
