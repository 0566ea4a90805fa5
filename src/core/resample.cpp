#include "core/resample.h"

#include <algorithm>
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

}  // namespace

void upscale_bilinear(const Framebuffer& from, Framebuffer& to) {
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
