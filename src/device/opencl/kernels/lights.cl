// Next-event estimation's light sampling, as render/lights.cpp: a triangle is chosen by
// binary search in the power CDF (the LightSampler's own table), a point on it by Heitz's
// low-distortion map (render/sampling.h).

typedef struct {
  float3 point;
  float3 normal;  // geometric, the emitting side
  float3 radiance;
  float pdf_area;  // selection probability / triangle area
} LightSample;

// Barycentrics (b1, b2) of a uniform point (Heitz 2019).
float2 sample_triangle(float u1, float u2) {
  float b0, b1;
  if (u2 > u1) {
    b0 = u1 * 0.5f;
    b1 = u2 - b0;
  } else {
    b1 = u2 * 0.5f;
    b0 = u1 - b1;
  }
  return (float2)(b1, 1.0f - b0 - b1);
}

// Veach's power heuristic (beta = 2).
float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// `count` > 0 lights. The first CDF entry greater than `u` (std::upper_bound) picks one.
LightSample sample_light(const __global Light* lights, const __global float* cdf, uint count,
                         float u, float u1, float u2) {
  uint lo = 0, hi = count;
  while (lo < hi) {
    const uint mid = lo + (hi - lo) / 2;
    if (u < cdf[mid]) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  const __global Light* l = &lights[min(lo, count - 1)];
  const float3 a = load3(l->a), b = load3(l->b), c = load3(l->c);
  const float2 bc = sample_triangle(u1, u2);
  LightSample s;
  s.point = a * (1.0f - bc.x - bc.y) + b * bc.x + c * bc.y;
  s.normal = normalize3(cross3(b - a, c - a));
  s.radiance = load3(l->radiance);
  s.pdf_area = l->pdf_area;
  return s;
}
