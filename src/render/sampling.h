// Warping functions from [0,1)^2 to directions and points, with their densities.
#pragma once

#include <cmath>

#include "core/math.h"

namespace multiray {

// Cosine-weighted direction about +z (local frame); pdf = cos(theta) / pi.
inline Vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1))};
}

// Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2
// (Heitz 2019, "A Low-Distortion Map Between Triangle and Square").
inline Vec2 sample_triangle(float u1, float u2) {
  float b0, b1;
  if (u2 > u1) {
    b0 = u1 * 0.5f;
    b1 = u2 - b0;
  } else {
    b1 = u2 * 0.5f;
    b0 = u1 - b1;
  }
  return {b1, 1.0f - b0 - b1};
}

// Veach's power heuristic (beta = 2) for two strategies.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0 ? a / (a + b) : 0.0f;
}

}  // namespace multiray
