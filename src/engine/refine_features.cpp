#include "engine/refine_features.h"

#include <algorithm>
#include <cmath>

namespace multiray {

void FeatureRefinement::restart(size_t pixels) {
  frames_ = 0;
  albedo_.assign(3 * pixels, 0.0), normal_.assign(3 * pixels, 0.0);
  emission_.assign(3 * pixels, 0.0);
  depth_.assign(pixels, 0.0), y_.assign(pixels, 0.0), y2_.assign(pixels, 0.0);
  m2_.assign(pixels, 0.0);
  depth_frames_.assign(pixels, 0);
}

void FeatureRefinement::add(const Framebuffer& image, int spp, FeatureBuffers& out) {
  const FeatureBuffers& f = image.features;
  const size_t n = image.pixels.size();
  ++frames_;
  out.resize(image.width, image.height);
  const double frames = frames_, s = spp, all = frames * s;
  for (size_t i = 0; i < n; ++i) {
    double len2 = 0;
    for (size_t c = 0; c < 3; ++c) {
      albedo_[3 * i + c] += f.albedo[3 * i + c];
      emission_[3 * i + c] += f.emission[3 * i + c];
      normal_[3 * i + c] += f.normal[3 * i + c];
      len2 += normal_[3 * i + c] * normal_[3 * i + c];
    }
    const double len = std::sqrt(len2);
    for (size_t c = 0; c < 3; ++c) {
      out.albedo[3 * i + c] = float(albedo_[3 * i + c] / frames);
      out.emission[3 * i + c] = float(emission_[3 * i + c] / frames);
      out.normal[3 * i + c] = len > 0 ? float(normal_[3 * i + c] / len) : 0.0f;
    }
    if (std::isfinite(f.depth[i])) depth_[i] += f.depth[i], ++depth_frames_[i];
    out.depth[i] = depth_frames_[i] > 0 ? float(depth_[i] / depth_frames_[i]) : INFINITY;
    // The variance is that of the beauty less its emission (render/shared/aov.h), so the
    // frames' means it pools are too.
    const Vec3 c = image.pixels[i];
    const float* e = &f.emission[3 * i];
    const double y = 0.2126 * (c.x - e[0]) + 0.7152 * (c.y - e[1]) + 0.0722 * (c.z - e[2]);
    y_[i] += y, y2_[i] += y * y;
    m2_[i] += double(f.variance[i]) * s * (s - 1);
    const double m2 = m2_[i] + s * std::max(0.0, y2_[i] - y_[i] * y_[i] / frames);
    out.variance[i] = all > 1 ? float(m2 / ((all - 1) * all)) : 0.0f;
  }
}

}  // namespace multiray
