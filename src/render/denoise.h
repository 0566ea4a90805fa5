// The denoiser: an edge-avoiding à-trous wavelet filter guided by the feature buffers
// (Dammertz et al. 2010) on the beauty demodulated by albedo, and, for animations and the
// viewer, SVGF's temporal accumulation with reprojection before it (Schied et al. 2017).
// The per-pixel steps are render/shared/denoise*.h, which the OpenCL driver
// (device/opencl/opencl_denoise.h) runs too; docs/noise.md describes the method.
//
// The filter is a pure function of full-frame buffers: run after the gather on the
// master, its image does not depend on how the frame was split (every pixel is computed
// from the whole frame's inputs alone, in any order, on any number of threads).
//
// Seam for the engine (issue 52, after the AOV branch merges): render/aov.h's
// FeatureBuffers hold exactly the layout DenoiseInput points into (no copies), so after
// the gather the master calls
//   DenoiseInput in{w, h, beauty, aov.albedo.data(), aov.normal.data(), aov.depth.data(),
//                   aov.variance.empty() ? nullptr : aov.variance.data(),
//                   aov.emission.empty() ? nullptr : aov.emission.data(), &view.camera};
//   denoise(in, resolve_denoise(choice, context), &state_of_view, out.data());
// with one DenoiseState per view kept across frames (reset when the scene changes), then
// hands `out` to the observers in place of the beauty (never to the raw EXR beauty).
#pragma once

#include <string>
#include <vector>

#include "render/shared/camera.h"
#include "scene/scene.h"

namespace multiray {

enum class DenoiseMethod { none, atrous, svgf };
// What `--denoise` takes: a method, or `auto` (resolve_denoise).
enum class DenoiseChoice { none, atrous, svgf, automatic };

// One frame's buffers, row-major, width x height (render/shared/denoise.h's layout), not
// owned. beauty, albedo, normal, depth are required; variance may be null (the filter
// then estimates it from the image); emission may be null (nothing is kept out of the
// filter); camera is needed by svgf only (null: no reprojection, every frame starts a new
// history).
struct DenoiseInput {
  int width = 0, height = 0;
  const float* beauty = nullptr;    // 3 a pixel, linear RGB
  const float* albedo = nullptr;    // 3 a pixel, linear RGB
  const float* normal = nullptr;    // 3 a pixel, unit, world space, 0 on a miss
  const float* depth = nullptr;     // 1 a pixel, along the camera axis, +inf on a miss
  const float* variance = nullptr;  // 1 a pixel, of the pixel mean's luminance
  // 3 a pixel, linear RGB: the beauty's emitted part (render/shared/aov.h), filtered out
  // and added back as it is (so a light's own pixels keep their values and its radiance
  // does not spread into its neighbours).
  const float* emission = nullptr;
  const Camera* camera = nullptr;
};

// The filter's parameters (defaults: SVGF's sigma_luminance and sigma_normal; ours for
// the rest, see docs/noise.md).
struct DenoiseParams {
  int iterations = 5;            // à-trous iterations, taps 1, 2, 4, ... 2^(n-1) apart
  float sigma_luminance = 4.0f;  // luminance difference, in standard deviations of noise
  // Exponent of the cosine of the angle by which a tap's normal turns beyond what the
  // pixel's own surface predicts (render/shared/denoise_normal.h; on a plane, the
  // normals' cosine).
  float sigma_normal = 128.0f;
  // true (ours, the default): the normal term allows for that turn; false: the normals'
  // cosine alone, the papers' term (`--denoise-normal svgf`).
  bool normal_turn = true;
  float sigma_depth = 0.02f;  // relative error of the planar prediction of 1/depth
  float sigma_albedo = 0.2f;  // largest albedo channel difference
  // svgf: least weight of the current frame, and what a reprojected history must match.
  float alpha = 0.2f, moments_alpha = 0.2f;
  float depth_tolerance = 0.05f;  // relative
  float normal_tolerance = 0.9f;  // cosine
  // svgf: true (the paper's form, Schied et al. 2017): the colour the next frame
  // accumulates onto is this frame's after the first à-trous iteration, so each frame
  // adds to a history already smoothed once; false (ours until 2026-12-04): the
  // unfiltered accumulation. The moments and history lengths are kept unfiltered either way.
  bool history_filtered = true;
};

// Whether svgf's history is taken after the first à-trous iteration (so the accumulation
// need not be kept as the history first): history_filtered, and there is an iteration.
inline bool svgf_history_from_first_iteration(const DenoiseParams& p) {
  return p.history_filtered && p.iterations > 0;
}

// svgf's history, kept by the caller between frames of one view. Empty: no history.
struct DenoiseState {
  int width = 0, height = 0;
  CameraBlock camera{};
  std::vector<float> color;          // accumulated demodulated colour, 3 a pixel
  std::vector<float> moments;        // luminance m1, m2 of the accumulated colour, 2 a pixel
  std::vector<float> history;        // frames accumulated n, variance of the colour, 2 a pixel
  std::vector<float> depth, normal;  // the frame's guides, to test the next one against
  bool empty() const { return color.empty(); }
  void reset() { *this = DenoiseState(); }
};

// The CPU filter's working buffers (guides, two colours, luminances and variances to
// ping-pong between iterations, svgf's new moments and history). A caller that denoises
// frame after frame keeps one and passes it to every call, so that a frame of the size of
// the last allocates nothing; what they hold between calls means nothing.
struct DenoiseBuffers {
  std::vector<float> guides, slopes;
  std::vector<float> color[2], luminance[2], variance[2];
  std::vector<float> moments, history;
};

// Writes the denoised image of `in` to `out_rgb` (3 floats a pixel, may not alias the
// inputs). none copies the beauty; atrous filters the frame alone; svgf accumulates into
// `temporal` first (required for svgf; reset when its size differs from the frame's) and
// filters the result (svgf accumulates the demodulated non-emitted part; each frame's own
// emission is added back after the filter). Throws std::invalid_argument on a missing buffer or a
// bad size. Rows are spread over the calling thread's TBB arena, each piece computed with
// denormals flushed to zero whatever the thread's own float mode; the result does not depend on
// the arena. `buffers` (may be null: allocated for the call) are reused when given.
void denoise(const DenoiseInput& in, DenoiseMethod method, DenoiseState* temporal, float* out_rgb,
             const DenoiseParams& params = {}, DenoiseBuffers* buffers = nullptr);

// `in` as the filter takes it: its variance left out when it says nothing. The renderer's
// variance needs two samples a pixel (render/shared/aov.h gives 0 with fewer), so a
// buffer that is 0 throughout, as every frame of one sample a pixel has, is no estimate;
// taken as one, it made the luminance weight shut out every neighbour of a lit pixel, and
// the viewer's 1-spp frames came out of the filter as noisy as they went in. Without it
// the filter estimates the variance itself, as SVGF does at one sample a pixel: spatially,
// and svgf from its temporal moments once a pixel has four frames. Both drivers call it.
DenoiseInput denoise_input_as_filtered(const DenoiseInput& in);

// Throws std::invalid_argument unless `in`, `temporal` and `out` are what denoise needs
// for `method` (the OpenCL driver checks its input with it too).
void check_denoise_input(const DenoiseInput& in, DenoiseMethod method,
                         const DenoiseState* temporal, const float* out);

// A registry entry: a `--denoise` value and its help line.
struct DenoiseMethodInfo {
  const char* name;
  DenoiseChoice choice;
  const char* help;
};
// none, atrous, svgf, auto: the values of `--denoise`, in the order help lists them.
const std::vector<DenoiseMethodInfo>& denoise_methods();
// The choice named `name`; false when there is none (`out` untouched).
bool parse_denoise(const std::string& name, DenoiseChoice& out);

// A registry entry: a `--denoise-normal` value (the normal term's form,
// DenoiseParams::normal_turn) and its help line.
struct DenoiseNormalInfo {
  const char* name;
  bool turn;
  const char* help;
};
// turn (ours, the default), svgf (the papers'): in the order help lists them.
const std::vector<DenoiseNormalInfo>& denoise_normal_terms();
// Sets params.normal_turn for the form named `name`; false when there is none (`params`
// untouched).
bool parse_denoise_normal(const std::string& name, DenoiseParams& params);

// What `auto` means for a run (issue 52): svgf in the viewer while the camera moves and
// while the image it shows has under 256 samples per pixel (`spp`: a still camera's
// refined image), atrous for PNG output under 256 samples per pixel, none otherwise (the
// raw EXR beauty is never touched unless asked). A named method is itself.
struct DenoiseContext {
  bool viewer = false, camera_moving = false;
  bool png_output = false;
  int spp = 1;
};
DenoiseMethod resolve_denoise(DenoiseChoice choice, const DenoiseContext& context);

}  // namespace multiray
