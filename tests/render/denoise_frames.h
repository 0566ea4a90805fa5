// Synthetic frames for the denoiser's tests (render/denoise.h): feature buffers of known
// geometry built in code, a clean beauty, and noise from a fixed seed, so the answer is
// known. Shared by the CPU tests and the OpenCL ones.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "render/denoise.h"
#include "render/path_tracer.h"

namespace multiray::testing {

struct DenoiseFrame {
  int width = 0, height = 0;
  std::vector<float> clean, beauty, albedo, normal, depth, variance, emission;
  Camera camera;
  bool with_variance = false;
  bool with_emission = false;  // the emission buffer is given to the filter

  DenoiseFrame(int w, int h) : width(w), height(h) {
    const size_t n = size_t(w) * size_t(h);
    clean.assign(3 * n, 0.0f), albedo.assign(3 * n, 0.0f), normal.assign(3 * n, 0.0f);
    depth.assign(n, INFINITY), variance.assign(n, 0.0f), emission.assign(3 * n, 0.0f);
  }
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  // Pixel (x, y) sees a surface of albedo `a`, normal `nrm` and depth `d` lit by
  // irradiance `e` (its clean beauty a * e).
  void set(int x, int y, Vec3 a, Vec3 e, Vec3 nrm, float d) {
    const size_t i = index(x, y);
    for (int c = 0; c < 3; ++c) {
      albedo[3 * i + size_t(c)] = a[c];
      clean[3 * i + size_t(c)] = a[c] * e[c];
      normal[3 * i + size_t(c)] = nrm[c];
    }
    depth[i] = d;
  }
  Vec3 clean_at(int x, int y) const {
    const size_t i = index(x, y);
    return Vec3(clean[3 * i], clean[3 * i + 1], clean[3 * i + 2]);
  }
  // The beauty: the clean one times (1 + N(0, sigma)), the same factor in every channel,
  // with the variance of the luminance that gives (given to the filter with
  // `pass_variance`).
  void add_noise(float sigma, unsigned seed, bool pass_variance) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, sigma);
    beauty = clean;
    for (size_t i = 0; i < depth.size(); ++i) {
      const float f = 1.0f + noise(rng);
      for (int c = 0; c < 3; ++c) beauty[3 * i + size_t(c)] *= f;
      const float l = luminance(Vec3(clean[3 * i], clean[3 * i + 1], clean[3 * i + 2]));
      variance[i] = l * l * sigma * sigma;
    }
    with_variance = pass_variance;
  }
  // Pixels [x0, x1) x [y0, y1) also see a light of radiance `le` (an emitter seen
  // directly, in the emission buffer): added to the beauty (after add_noise) and the
  // clean image, and given to the filter.
  void add_light(int x0, int y0, int x1, int y1, Vec3 le) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int c = 0; c < 3; ++c) {
          const size_t k = 3 * index(x, y) + size_t(c);
          beauty[k] += le[c], clean[k] += le[c], emission[k] += le[c];
        }
    with_emission = true;
  }
  DenoiseInput input() const {
    DenoiseInput in{width,
                    height,
                    beauty.data(),
                    albedo.data(),
                    normal.data(),
                    depth.data(),
                    with_variance ? variance.data() : nullptr,
                    with_emission ? emission.data() : nullptr};
    in.camera = &camera;
    return in;
  }
};

// Root-mean-square difference between `image` and the frame's clean beauty over the
// pixels (x, y) with pred(x, y).
template <class Pred>
double rmse(const DenoiseFrame& f, const std::vector<float>& image, Pred pred) {
  double sum = 0;
  size_t count = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      if (!pred(x, y)) continue;
      const size_t i = f.index(x, y);
      for (int c = 0; c < 3; ++c) {
        const double d = double(image[3 * i + size_t(c)]) - double(f.clean[3 * i + size_t(c)]);
        sum += d * d;
      }
      ++count;
    }
  return std::sqrt(sum / double(3 * count));
}

// Which side of the hard edge an edge frame's pixel lies on.
enum class EdgeKind { normal, depth, albedo };

// Two flat regions meeting at x = width / 2: on the left albedo 0.7, irradiance 1, normal
// +z, depth 2. On the right one guide differs: a normal tilted 60 degrees and irradiance
// 0.25 (normal), depth 3 and irradiance 0.25 (depth), or albedo 0.2 and irradiance 0.25
// (albedo: another material, which reflects the light differently).
inline DenoiseFrame edge_frame(EdgeKind kind, int w = 64, int h = 48) {
  DenoiseFrame f(w, h);
  const Vec3 nz(0, 0, 1), tilted(std::sin(1.0472f), 0.0f, std::cos(1.0472f));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x < w / 2) {
        f.set(x, y, Vec3(0.7f), Vec3(1.0f), nz, 2.0f);
      } else if (kind == EdgeKind::normal) {
        f.set(x, y, Vec3(0.7f), Vec3(0.25f), tilted, 2.0f);
      } else if (kind == EdgeKind::depth) {
        f.set(x, y, Vec3(0.7f), Vec3(0.25f), nz, 3.0f);
      } else {
        f.set(x, y, Vec3(0.2f), Vec3(0.25f), nz, 2.0f);
      }
    }
  return f;
}

// A near wall (world x < 0, z = -2, bright) in front of a far wall (z = -4, dark) seen
// by `cam` in a kWallsWidth x kWallsHeight image, noise `sigma` from `seed`, the variance
// given: an analytic scene for SVGF's reprojection.
constexpr int kWallsWidth = 64, kWallsHeight = 48;

inline Camera camera_at(float x) {
  return Camera{Vec3(x, 0, 0), Vec3(x, 0, -1), Vec3(0, 1, 0), 60.0f};
}

inline DenoiseFrame walls(const Camera& cam, unsigned seed, float sigma = 0.3f) {
  const int w = kWallsWidth, h = kWallsHeight;
  DenoiseFrame f(w, h);
  f.camera = cam;
  const PinholeCamera pc(cam, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray r = pc.ray(float(x) + 0.5f, float(y) + 0.5f);
      const float t_near = (-2.0f - r.org.z) / r.dir.z;
      const bool near = r.org.x + t_near * r.dir.x < 0.0f;
      const float t = near ? t_near : (-4.0f - r.org.z) / r.dir.z;
      f.set(x, y, Vec3(0.8f), Vec3(near ? 1.0f : 0.1f), Vec3(0, 0, 1), t * dot(r.dir, pc.forward));
    }
  f.add_noise(sigma, seed, true);
  return f;
}

}  // namespace multiray::testing
