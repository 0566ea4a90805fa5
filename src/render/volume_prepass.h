// The pre-pass of Bruder, Frey & Ertl 2017 (§4): before a frame, cheap coarse rays find
// where each part of the image will march. Per coarse pixel it gives the span through
// non-empty blocks (D_front, D_back, from the block opacities: exact, as the paper's
// rasterised hull) and an estimate of where early ray termination will stop the ray
// (D'_ERT): the ray walks the blocks' 16-bin opacity histograms, drawing one opacity per
// block at random, until the accumulated opacity reaches the termination threshold.
// The paper takes min(D_back, D'_ERT) - D_front over the step as the predicted number of
// samples (the analytic part of its cost model); we sum the lengths of the non-empty
// blocks up to D'_ERT instead, since our raycaster also skips empty blocks between D_front
// and D_back (on a ball in a 40^3 volume the span overestimated edge rays by up to 80%).
#pragma once

#include <cstdint>
#include <vector>

#include "render/render_types.h"
#include "render/volume_raycaster.h"

namespace multiray {

struct VolumePrepass {
  int stride = 1;             // output pixels per coarse pixel, each way
  int width = 0, height = 0;  // coarse grid: ceil(view size / stride)
  // Per coarse pixel, row-major: predicted marched length (world units: non-empty blocks
  // up to the estimated termination) and the span through non-empty blocks (front > back
  // when the ray sees none).
  std::vector<float> marched, front, back;
  // Per coarse pixel: blocks the raycaster's walk visits before the estimated termination
  // (a cost per ray that the step does not change).
  std::vector<float> blocks;
  // Per coarse pixel: the marched length weighted by the cost of its samples, 1 for a
  // shaded sample (7 fetches) and 1/7 for a transparent one (1 fetch), by each block's
  // VolumeStyle::shaded_fraction. Our refinement of the paper's 7 fetches per sample: the
  // raycaster shades only visible samples, so a transfer-function switch changes the cost
  // per sample by up to 7x.
  std::vector<float> weighted;
  // Features of the frame for the learned part of the model.
  double mean_marched = 0;  // world units, over all coarse pixels
  double max_depth = 0;     // longest span back - front, world units
};

// Runs the pre-pass of `view` with `style` (its block opacities and termination
// threshold); one coarse ray through the centre of each stride x stride block of pixels.
// Random opacities are keyed by (coarse pixel, frame, view, seed): the same inputs give
// the same estimate. Parallel (oneTBB) over rows.
VolumePrepass run_prepass(const VolumeScene& vs, const VolumeStyle& style, const ViewSetup& view,
                          int stride, uint64_t seed);

}  // namespace multiray
