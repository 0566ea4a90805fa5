#include "core/math.h"

namespace multiray {

Mat4 Mat4::normal_matrix() const {
  const float a = m[0][0], b = m[0][1], c = m[0][2];
  const float d = m[1][0], e = m[1][1], f = m[1][2];
  const float g = m[2][0], h = m[2][1], i = m[2][2];
  const float det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  Mat4 r;
  if (det == 0) return r;
  const float s = 1.0f / det;
  // Inverse (adjugate / det), then transposed.
  r.m[0][0] = (e * i - f * h) * s, r.m[1][0] = (c * h - b * i) * s,
  r.m[2][0] = (b * f - c * e) * s;
  r.m[0][1] = (f * g - d * i) * s, r.m[1][1] = (a * i - c * g) * s,
  r.m[2][1] = (c * d - a * f) * s;
  r.m[0][2] = (d * h - e * g) * s, r.m[1][2] = (b * g - a * h) * s,
  r.m[2][2] = (a * e - b * d) * s;
  return r;
}

}  // namespace multiray
