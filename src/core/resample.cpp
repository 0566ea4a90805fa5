#include "core/resample.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace multiray {

namespace {

// One axis of the interpolation: the two source indices and the weight of the second.
struct Tap {
  int i0, i1;
  float w1;
};

std::vector<Tap> taps(int to, int from) {
  std::vector<Tap> t(static_cast<size_t>(to));
  const double ratio = double(from) / double(to);
  for (int i = 0; i < to; ++i) {
    const double s = std::clamp((i + 0.5) * ratio - 0.5, 0.0, double(from - 1));
    const int i0 = std::min(int(s), from - 1);
    t[size_t(i)] = Tap{i0, std::min(i0 + 1, from - 1), float(s - i0)};
  }
  return t;
}

// Whether 1/depth runs on smoothly from source pixel i0 to its neighbour i1 along one
// axis (k-th pixel at inv[k * stride], n of them; 0 on a miss), as on one surface: the
// step from i0 to i1 is the step beside the pair (i0 - 1 to i0, or i1 to i1 + 1) within
// 5% (svgf's depth tolerance) of 1/depth and once more that step. 1/depth is affine along
// a plane, so its steps are equal there; the margin of one step is for the pixels'
// depths being means over jittered samples, at 1 spp off their centre's by a good part
// of a step. A silhouette between the two is a jump neither side's step predicts (the
// continuation from beside the pair is what render/shared/denoise.h's slopes do too).
// Misses are no surface; i0 == i1 (a clamped tap) is one pixel.
bool smooth_pair(const float* inv, size_t stride, int n, int i0, int i1) {
  if (i0 == i1) return true;
  const auto at = [&](int k) { return inv[size_t(k) * stride]; };
  const float a = at(i0), b = at(i1), jump = b - a, tolerance = 0.05f * std::max(a, b);
  if (!(a > 0 && b > 0)) return false;
  const auto continues = [&](float step) {
    return std::abs(jump - step) <= tolerance + std::abs(step);
  };
  bool beside = false;
  if (i0 > 0 && at(i0 - 1) > 0) {
    beside = true;
    if (continues(a - at(i0 - 1))) return true;
  }
  if (i1 + 1 < n && at(i1 + 1) > 0) {
    beside = true;
    if (continues(at(i1 + 1) - b)) return true;
  }
  return !beside && std::abs(jump) <= tolerance;  // nothing beside: close values only
}

// Output pixel `o` of `to` from the four taps `at` of `from` with weights `w` (inv: 1/depth
// of `from`): upscale_features's rules, the depth of tap `nearest` unless it is -1.
void blend(const FeatureBuffers& from, const std::vector<float>& inv, const size_t (&at)[4],
           const float (&w)[4], int nearest, FeatureBuffers& to, size_t o) {
  float albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0}, emission[3] = {0, 0, 0}, variance = 0,
        inverse_depth = 0;
  for (int k = 0; k < 4; ++k) {
    for (size_t c = 0; c < 3; ++c) {
      albedo[c] += w[k] * from.albedo[3 * at[k] + c];
      normal[c] += w[k] * from.normal[3 * at[k] + c];
      emission[c] += w[k] * from.emission[3 * at[k] + c];
    }
    variance += w[k] * w[k] * from.variance[at[k]];
    inverse_depth += w[k] * inv[at[k]];
  }
  const float length =
      std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  for (size_t c = 0; c < 3; ++c) {
    to.albedo[3 * o + c] = albedo[c];
    to.emission[3 * o + c] = emission[c];
    to.normal[3 * o + c] = length > 0 ? normal[c] / length : 0.0f;
  }
  to.variance[o] = variance;
  to.depth[o] = nearest < 0 ? 1.0f / inverse_depth : from.depth[at[nearest]];
}

}  // namespace

void upscale_features(const FeatureBuffers& from, int to_width, int to_height,
                      FeatureBuffers& to) {
  if (from.width == to_width && from.height == to_height) {
    to = from;
    return;
  }
  to.resize(to_width, to_height);
  const std::vector<Tap> tx = taps(to_width, from.width), ty = taps(to_height, from.height);
  const size_t fw = size_t(from.width);
  std::vector<float> inv(from.depth.size());  // 1/depth, 0 on a miss (1/inf)
  for (size_t i = 0; i < inv.size(); ++i) inv[i] = 1.0f / from.depth[i];
  // The four taps are one surface: both rows smooth across, both columns down.
  const auto one_surface = [&](const Tap& u, const Tap& v) {
    const float* row0 = &inv[size_t(v.i0) * fw];
    const float* row1 = &inv[size_t(v.i1) * fw];
    return smooth_pair(row0, 1, from.width, u.i0, u.i1) &&
           smooth_pair(row1, 1, from.width, u.i0, u.i1) &&
           smooth_pair(&inv[size_t(u.i0)], fw, from.height, v.i0, v.i1) &&
           smooth_pair(&inv[size_t(u.i1)], fw, from.height, v.i0, v.i1);
  };
  for (int y = 0; y < to_height; ++y) {
    const Tap& v = ty[size_t(y)];
    for (int x = 0; x < to_width; ++x) {
      const Tap& u = tx[size_t(x)];
      // The four taps (top left, top right, bottom left, bottom right) and their weights.
      const size_t y0 = size_t(v.i0) * fw, y1 = size_t(v.i1) * fw;
      const size_t at[4] = {y0 + size_t(u.i0), y0 + size_t(u.i1), y1 + size_t(u.i0),
                            y1 + size_t(u.i1)};
      const float w[4] = {(1 - u.w1) * (1 - v.w1), u.w1 * (1 - v.w1), (1 - u.w1) * v.w1,
                          u.w1 * v.w1};
      const size_t o = size_t(y) * size_t(to_width) + size_t(x);
      const int nearest = (v.w1 < 0.5f ? 0 : 2) + (u.w1 < 0.5f ? 0 : 1);
      blend(from, inv, at, w, one_surface(u, v) ? -1 : nearest, to, o);
    }
  }
}

void upscale_bilinear(const Framebuffer& from, Framebuffer& to) {
  if (from.features.empty())
    to.features.clear();
  else
    upscale_features(from.features, to.width, to.height, to.features);
  if (from.width == to.width && from.height == to.height) {
    to.pixels = from.pixels;
    to.alpha = from.alpha;
    return;
  }
  const std::vector<Tap> tx = taps(to.width, from.width), ty = taps(to.height, from.height);
  to.alpha.resize(from.alpha.empty() ? 0 : to.pixels.size());
  const auto alpha = [&](int x, int y) { return from.alpha[size_t(y) * size_t(from.width) + x]; };
  for (int y = 0; y < to.height; ++y) {
    const Tap& v = ty[size_t(y)];
    for (int x = 0; x < to.width; ++x) {
      const Tap& u = tx[size_t(x)];
      const Vec3 top = from.at(u.i0, v.i0) * (1.0f - u.w1) + from.at(u.i1, v.i0) * u.w1;
      const Vec3 bottom = from.at(u.i0, v.i1) * (1.0f - u.w1) + from.at(u.i1, v.i1) * u.w1;
      to.at(x, y) = top * (1.0f - v.w1) + bottom * v.w1;
      if (to.alpha.empty()) continue;
      const float a_top = alpha(u.i0, v.i0) * (1.0f - u.w1) + alpha(u.i1, v.i0) * u.w1;
      const float a_bottom = alpha(u.i0, v.i1) * (1.0f - u.w1) + alpha(u.i1, v.i1) * u.w1;
      to.alpha[size_t(y) * size_t(to.width) + x] = a_top * (1.0f - v.w1) + a_bottom * v.w1;
    }
  }
}

}  // namespace multiray
