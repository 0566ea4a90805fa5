#include "render/denoise.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "render/path_tracer.h"
#include "render/shared/denoise_atrous.h"
#include "render/shared/denoise_temporal.h"

namespace multiray {

namespace {

// Calls f(x, y) for every pixel, rows spread over the calling thread's TBB arena. Each
// pixel is written by one call that reads only buffers no call writes, so the result is
// the same for any number of threads.
template <class F>
void for_each_denoise_pixel(int width, int height, F f) {
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, height),
                            [&](const oneapi::tbb::blocked_range<int>& rows) {
                              for (int y = rows.begin(); y < rows.end(); ++y)
                                for (int x = 0; x < width; ++x) f(x, y);
                            });
}

DenoiseWeights denoise_weights_of(const DenoiseParams& p) {
  return DenoiseWeights{p.sigma_luminance, p.sigma_normal, p.sigma_depth, p.sigma_albedo};
}

// The frame's buffers as the shared steps read them: demodulated colour and its variance
// (the renderer's, scaled, or the spatial estimate).
struct DemodulatedFrame {
  std::vector<float> color, variance;
};

DemodulatedFrame demodulate_frame(const DenoiseInput& in, const DenoiseWeights& w) {
  const size_t n = size_t(in.width) * size_t(in.height);
  DemodulatedFrame d{std::vector<float>(3 * n), std::vector<float>(n)};
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    denoise_demodulate(in.beauty, in.albedo, in.depth, in.variance, in.variance != nullptr,
                       d.color.data(), d.variance.data(), y * in.width + x);
  });
  if (!in.variance)
    for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
      d.variance[size_t(y) * size_t(in.width) + size_t(x)] = denoise_spatial_variance(
          d.color.data(), in.albedo, in.normal, in.depth, in.width, in.height, x, y, &w);
    });
  return d;
}

// The à-trous iterations on `color` and `variance` (both overwritten with the result).
void run_atrous(const DenoiseInput& in, const DenoiseParams& p, std::vector<float>& color,
                std::vector<float>& variance) {
  const DenoiseWeights w = denoise_weights_of(p);
  std::vector<float> color2(color.size()), variance2(variance.size());
  for (int k = 0; k < p.iterations; ++k) {
    const int step = 1 << k;
    for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
      denoise_atrous_pixel(color.data(), variance.data(), in.albedo, in.normal, in.depth,
                           color2.data(), variance2.data(), in.width, in.height, x, y, step, &w);
    });
    color.swap(color2);
    variance.swap(variance2);
  }
}

void remodulate_frame(const DenoiseInput& in, const std::vector<float>& color, float* out) {
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    denoise_remodulate(color.data(), in.albedo, in.depth, out, y * in.width + x);
  });
}

// svgf's temporal step: the frame's demodulated colour accumulated into `s`, whose
// colour and variance it replaces `d`'s with; `s` then holds this frame's history.
void accumulate_frame(const DenoiseInput& in, const DenoiseParams& p, DemodulatedFrame& d,
                      DenoiseState& s) {
  const size_t n = size_t(in.width) * size_t(in.height);
  if (s.width != in.width || s.height != in.height) s.reset();
  CameraBlock cam{};
  if (in.camera) cam = PinholeCamera(*in.camera, in.width, in.height).block();
  const bool has_previous = !s.empty() && in.camera;
  const TemporalParams t{p.alpha, p.moments_alpha, p.depth_tolerance, p.normal_tolerance,
                         in.variance != nullptr};
  std::vector<float> color(3 * n), moments(2 * n), history(2 * n);
  const float* none = d.variance.data();  // never read without a previous frame
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    denoise_temporal_pixel(
        &cam, &s.camera, has_previous, d.color.data(), d.variance.data(), in.depth, in.normal,
        has_previous ? s.color.data() : none, has_previous ? s.moments.data() : none,
        has_previous ? s.history.data() : none, has_previous ? s.depth.data() : none,
        has_previous ? s.normal.data() : none, color.data(), moments.data(), history.data(),
        in.width, in.height, x, y, &t);
  });
  d.color = color;
  for (size_t i = 0; i < n; ++i) d.variance[i] = history[2 * i + 1];
  s.width = in.width, s.height = in.height, s.camera = cam;
  s.color = std::move(color);
  s.moments = std::move(moments);
  s.history = std::move(history);
  s.depth.assign(in.depth, in.depth + n);
  s.normal.assign(in.normal, in.normal + 3 * n);
}

}  // namespace

void check_denoise_input(const DenoiseInput& in, DenoiseMethod method,
                         const DenoiseState* temporal, const float* out) {
  if (in.width <= 0 || in.height <= 0)
    throw std::invalid_argument("denoise: the image has no pixels");
  if (!in.beauty || !out) throw std::invalid_argument("denoise: no beauty or no output");
  if (method != DenoiseMethod::none && (!in.albedo || !in.normal || !in.depth))
    throw std::invalid_argument("denoise: the filter needs albedo, normal and depth");
  if (method == DenoiseMethod::svgf && !temporal)
    throw std::invalid_argument("denoise: svgf needs a state to keep its history in");
}

void denoise(const DenoiseInput& in, DenoiseMethod method, DenoiseState* temporal, float* out_rgb,
             const DenoiseParams& params) {
  check_denoise_input(in, method, temporal, out_rgb);
  const size_t n = size_t(in.width) * size_t(in.height);
  if (method == DenoiseMethod::none) {
    std::memcpy(out_rgb, in.beauty, 3 * n * sizeof(float));
    return;
  }
  DemodulatedFrame d = demodulate_frame(in, denoise_weights_of(params));
  if (method == DenoiseMethod::svgf) accumulate_frame(in, params, d, *temporal);
  run_atrous(in, params, d.color, d.variance);
  remodulate_frame(in, d.color, out_rgb);
}

const std::vector<DenoiseMethodInfo>& denoise_methods() {
  static const std::vector<DenoiseMethodInfo> methods{
      {"none", DenoiseChoice::none, "no denoising: the path tracer's image as it is"},
      {"atrous", DenoiseChoice::atrous,
       "edge-avoiding à-trous wavelet filter (Dammertz et al. 2010) guided by albedo, normal "
       "and depth, on the beauty divided by albedo; each frame alone"},
      {"svgf", DenoiseChoice::svgf,
       "spatiotemporal variance-guided filtering (Schied et al. 2017): the frames accumulated "
       "through reprojection, then the à-trous filter guided by their variance"},
      {"auto", DenoiseChoice::automatic,
       "svgf in the viewer while the camera moves and while its still image has under 256 "
       "samples per pixel, atrous for PNG output under 256 samples per pixel, none otherwise"},
  };
  return methods;
}

bool parse_denoise(const std::string& name, DenoiseChoice& out) {
  for (const DenoiseMethodInfo& m : denoise_methods())
    if (name == m.name) {
      out = m.choice;
      return true;
    }
  return false;
}

DenoiseMethod resolve_denoise(DenoiseChoice choice, const DenoiseContext& c) {
  switch (choice) {
    case DenoiseChoice::none:
      return DenoiseMethod::none;
    case DenoiseChoice::atrous:
      return DenoiseMethod::atrous;
    case DenoiseChoice::svgf:
      return DenoiseMethod::svgf;
    case DenoiseChoice::automatic:
      break;
  }
  if (c.viewer) return c.camera_moving || c.spp < 256 ? DenoiseMethod::svgf : DenoiseMethod::none;
  return c.png_output && c.spp < 256 ? DenoiseMethod::atrous : DenoiseMethod::none;
}

}  // namespace multiray
