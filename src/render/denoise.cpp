#include "render/denoise.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "render/denoise_rows.h"
#include "render/path_tracer.h"
#include "render/shared/denoise_temporal.h"

namespace multiray {

namespace {

// Flush-to-zero and denormals-are-zero on the calling thread for its lifetime (the MXCSR
// it found is restored after). Every piece of the filter runs under it, so a pixel is
// the same whichever thread computes it: TBB workers that once joined a CPU device's
// arena keep that device's fast float mode (device/cpu/thread_setup.h), the calling
// thread may not have it. It also keeps tiny weights (a cosine's 128th power, exp of a
// large negative exponent) from taking the slow path of subnormal arithmetic.
class FlushDenormals {
 public:
  FlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushZero | kDenormalsZero); }
  ~FlushDenormals() { _mm_setcsr(saved_); }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  static constexpr unsigned kFlushZero = 0x8000, kDenormalsZero = 0x0040;
  unsigned saved_;
};

// Calls f(y) for every row, rows spread over the calling thread's TBB arena. Each pixel
// is written by one call that reads only buffers no call writes, so the result is the
// same for any number of threads.
template <class F>
void for_each_denoise_row(int height, F f) {
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, height),
                            [&](const oneapi::tbb::blocked_range<int>& rows) {
                              const FlushDenormals mode;
                              for (int y = rows.begin(); y < rows.end(); ++y) f(y);
                            });
}

// Calls f(x, y) for every pixel (for_each_denoise_row).
template <class F>
void for_each_denoise_pixel(int width, int height, F f) {
  for_each_denoise_row(height, [&](int y) {
    for (int x = 0; x < width; ++x) f(x, y);
  });
}

DenoiseWeights denoise_weights_of(const DenoiseParams& p) {
  return denoise_weights(p.sigma_luminance, p.sigma_normal, p.sigma_depth, p.sigma_albedo,
                         p.normal_turn ? 1 : 0);
}

// Sizes `v` to `n` floats (kept when it has them: the values are overwritten).
void size_to(std::vector<float>& v, size_t n) {
  if (v.size() != n) v.resize(n);
}

// The frame's guides, and its demodulated colour, luminance and variance (the renderer's,
// scaled, or the spatial estimate) in slot 0 of `b`. Without `start_variance` the
// variance is 0 throughout instead (svgf without a given variance estimates it after its
// temporal step, where a pixel needs it: accumulate_frame).
void prepare_frame(const DenoiseInput& in, const DenoiseWeights& w, DenoiseBuffers& b,
                   bool start_variance) {
  const size_t n = size_t(in.width) * size_t(in.height);
  size_to(b.guides, MR_DENOISE_GUIDE_FLOATS * n);
  size_to(b.slopes, MR_DENOISE_SLOPE_FLOATS * n);
  for (int k = 0; k < 2; ++k) {
    size_to(b.color[k], 3 * n);
    size_to(b.luminance[k], n);
    size_to(b.variance[k], n);
  }
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    denoise_pack_guides(in.albedo, in.normal, in.depth, in.width, in.height, x, y, b.guides.data(),
                        b.slopes.data());
    denoise_demodulate(in.beauty, in.emission, in.emission != nullptr, in.albedo, in.depth,
                       in.variance, in.variance != nullptr, b.color[0].data(),
                       b.luminance[0].data(), b.variance[0].data(), y * in.width + x);
  });
  if (!start_variance) {
    std::fill(b.variance[0].begin(), b.variance[0].end(), 0.0f);
    return;
  }
  // The variance to start from (denoise_start_variance), into slot 1, then swapped in.
  DenoisePass pass;
  pass.width = in.width, pass.height = in.height, pass.weights = w;
  pass.luminance = b.luminance[0].data(), pass.variance = b.variance[0].data();
  pass.guides = b.guides.data(), pass.slopes = b.slopes.data();
  pass.variance_out = b.variance[1].data();
  for_each_denoise_row(
      in.height, [&](int y) { denoise_start_variance_row(pass, y, in.variance != nullptr); });
  std::swap(b.variance[0], b.variance[1]);
}

// The à-trous iterations, from slot `cur` of `b`; returns the slot holding the result.
// `first` (may be null): given the first iteration's colour (svgf's filtered history).
int run_atrous(const DenoiseInput& in, const DenoiseParams& p, DenoiseBuffers& b, int cur,
               std::vector<float>* first = nullptr) {
  const DenoiseWeights w = denoise_weights_of(p);
  for (int k = 0; k < p.iterations; ++k, cur ^= 1) {
    const int step = 1 << k, next = cur ^ 1;
    DenoisePass pass;
    pass.width = in.width, pass.height = in.height, pass.weights = w;
    pass.color = b.color[cur].data(), pass.luminance = b.luminance[cur].data();
    pass.variance = b.variance[cur].data();
    pass.guides = b.guides.data(), pass.slopes = b.slopes.data();
    pass.color_out = b.color[next].data(), pass.luminance_out = b.luminance[next].data();
    pass.variance_out = b.variance[next].data();
    for_each_denoise_row(in.height, [&](int y) { denoise_atrous_row(pass, y, step); });
    if (k == 0 && first) first->assign(b.color[next].begin(), b.color[next].end());
  }
  return cur;
}

void remodulate_frame(const DenoiseInput& in, const std::vector<float>& color, float* out) {
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    denoise_remodulate(color.data(), in.emission, in.emission != nullptr, in.albedo, in.depth, out,
                       y * in.width + x);
  });
}

// Without a given variance: the frame's share of the variance of every pixel whose
// history is young, from the spatial estimate (denoise_young_history_row), into b.history
// and slot 1's variance. The temporal step took it as 0 (prepare_frame without its start
// variance): the same bits as with the estimate made for every pixel first, which SVGF
// (section 4.2) uses only for histories under four frames.
void add_young_history_variance(const DenoiseInput& in, const DenoiseParams& p,
                                DenoiseBuffers& b) {
  DenoisePass pass;
  pass.width = in.width, pass.height = in.height, pass.weights = denoise_weights_of(p);
  pass.luminance = b.luminance[0].data();
  pass.guides = b.guides.data(), pass.slopes = b.slopes.data();
  pass.variance_out = b.variance[1].data();
  for_each_denoise_row(
      in.height, [&](int y) { denoise_young_history_row(pass, y, b.history.data(), p.alpha); });
}

// svgf's temporal step: the frame's demodulated colour (slot 0 of `b`) accumulated into
// `s`, the accumulated colour, its luminance and variance written to slot 1 for the
// filter; `s` then holds this frame's history. Returns 1, the filter's slot.
int accumulate_frame(const DenoiseInput& in, const DenoiseParams& p, DenoiseBuffers& b,
                     DenoiseState& s) {
  const size_t n = size_t(in.width) * size_t(in.height);
  if (s.width != in.width || s.height != in.height) s.reset();
  CameraBlock cam{};
  if (in.camera) cam = PinholeCamera(*in.camera, in.width, in.height).block();
  const bool has_previous = !s.empty() && in.camera;
  const TemporalParams t{p.alpha, p.moments_alpha, p.depth_tolerance, p.normal_tolerance,
                         in.variance != nullptr};
  size_to(b.moments, 2 * n);
  size_to(b.history, 2 * n);
  const float* none = b.variance[0].data();  // never read without a previous frame
  float* color = b.color[1].data();
  for_each_denoise_pixel(in.width, in.height, [&](int x, int y) {
    const int i = y * in.width + x;
    denoise_temporal_pixel(
        &cam, &s.camera, has_previous, b.color[0].data(), b.variance[0].data(), in.depth,
        in.normal, has_previous ? s.color.data() : none, has_previous ? s.moments.data() : none,
        has_previous ? s.history.data() : none, has_previous ? s.depth.data() : none,
        has_previous ? s.normal.data() : none, color, b.moments.data(), b.history.data(), in.width,
        in.height, x, y, &t);
    denoise_store_luminance(color, b.luminance[1].data(), i);
    b.variance[1][size_t(i)] = b.history[2 * size_t(i) + 1];
  });
  if (!in.variance) add_young_history_variance(in, p, b);
  s.width = in.width, s.height = in.height, s.camera = cam;
  // Else run_atrous writes the history after its first iteration.
  if (!svgf_history_from_first_iteration(p)) s.color.assign(b.color[1].begin(), b.color[1].end());
  s.moments.swap(b.moments);  // b's become the scratch of the next frame
  s.history.swap(b.history);
  s.depth.assign(in.depth, in.depth + n);
  s.normal.assign(in.normal, in.normal + 3 * n);
  return 1;
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

DenoiseInput denoise_input_as_filtered(const DenoiseInput& in) {
  DenoiseInput out = in;
  const size_t n = size_t(std::max(in.width, 0)) * size_t(std::max(in.height, 0));
  if (in.variance && std::none_of(in.variance, in.variance + n, [](float v) { return v > 0.0f; }))
    out.variance = nullptr;
  return out;
}

void denoise(const DenoiseInput& given, DenoiseMethod method, DenoiseState* temporal,
             float* out_rgb, const DenoiseParams& params, DenoiseBuffers* buffers) {
  check_denoise_input(given, method, temporal, out_rgb);
  const DenoiseInput in = denoise_input_as_filtered(given);
  const size_t n = size_t(in.width) * size_t(in.height);
  if (method == DenoiseMethod::none) {
    std::memcpy(out_rgb, in.beauty, 3 * n * sizeof(float));
    return;
  }
  DenoiseBuffers local;
  DenoiseBuffers& b = buffers ? *buffers : local;
  const bool svgf = method == DenoiseMethod::svgf;
  prepare_frame(in, denoise_weights_of(params), b, !svgf || in.variance);
  int cur = 0;
  if (svgf) cur = accumulate_frame(in, params, b, *temporal);
  cur = run_atrous(in, params, b, cur,
                   svgf && svgf_history_from_first_iteration(params) ? &temporal->color : nullptr);
  remodulate_frame(in, b.color[cur], out_rgb);
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

const std::vector<DenoiseNormalInfo>& denoise_normal_terms() {
  static const std::vector<DenoiseNormalInfo> terms{
      {"turn", true,
       "ours: the normals' cosine beyond the turn the pixel's own surface predicts, so that "
       "curved surfaces (columns, arches) are filtered along while a crease still stops the "
       "filter"},
      {"svgf", false,
       "the papers' term (Schied et al. 2017, after Dammertz et al. 2010): the normals' "
       "cosine alone, raised to 128"},
  };
  return terms;
}

bool parse_denoise_normal(const std::string& name, DenoiseParams& params) {
  for (const DenoiseNormalInfo& t : denoise_normal_terms())
    if (name == t.name) {
      params.normal_turn = t.turn;
      return true;
    }
  return false;
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
