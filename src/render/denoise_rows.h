// The CPU's passes of the à-trous filter (render/shared/denoise_atrous.h), one image row
// at a time: render/denoise.cpp spreads the rows over threads. A row's pixels go
// kDenoiseLanes at a time wherever each column of taps lies inside the image for all of
// them or for none (all but a few pixels beside the left and right edges): such a block
// of neighbours is filtered tap by tap, every tap of every pixel, by the shared dialect's
// branch-free functions in loops over the block that the compiler turns into vector
// instructions (a tap of weight 0 adds 0); its pixels' taps and guides are neighbours in
// memory. The other pixels take the shared per-pixel functions, as the OpenCL driver
// does. A pixel gets the same bits either way (Denoise.BlocksComputeWhatPixelsDo): the
// same operations in the same order, only computed for several pixels at once.
#pragma once

#include "render/shared/denoise.h"

namespace multiray {

// Pixels filtered together: two SSE2 vectors, one AVX2 vector.
constexpr int kDenoiseLanes = 8;

// One pass's frame and buffers (render/shared/denoise.h's layouts), not owned.
struct DenoisePass {
  int width = 0, height = 0;
  const float* color = nullptr;      // 3 a pixel (the à-trous iterations only)
  const float* luminance = nullptr;  // of `color` (of the demodulated beauty: the start)
  const float* variance = nullptr;   // the iteration's; the given one for the start
  const float* guides = nullptr;     // denoise_pack_guides's planes
  const float* slopes = nullptr;
  float* color_out = nullptr;
  float* luminance_out = nullptr;
  float* variance_out = nullptr;  // the only output of the start
  DenoiseWeights weights{};
};

// One à-trous iteration (denoise_atrous_pixel) with taps `step` apart, over row y.
// `blocks` false: every pixel by the per-pixel function (what blocks are tested against).
// Returns how many of the row's pixels went by blocks.
int denoise_atrous_row(const DenoisePass& pass, int y, int step, bool blocks = true);

// The variance the filter starts from (denoise_start_variance) over row y into
// pass.variance_out; `has_variance`: pass.variance is the given one. Returns how many of
// the row's pixels went by blocks.
int denoise_start_variance_row(const DenoisePass& pass, int y, bool has_variance,
                               bool blocks = true);

// svgf without a given variance, after its temporal step over row y: each pixel whose
// history is young (denoise_history_young of history[2 i]) gets its frame's share of the
// variance from the spatial estimate of pass.luminance (the frame's demodulated
// luminance), denoise_young_history_variance into history[2 i + 1] and
// pass.variance_out; the other pixels, whose variance came from the moments, are left
// as they are. `alpha`: TemporalParams::alpha. Returns how many of the row's pixels went
// by blocks.
int denoise_young_history_row(const DenoisePass& pass, int y, float* history, float alpha,
                              bool blocks = true);

}  // namespace multiray
