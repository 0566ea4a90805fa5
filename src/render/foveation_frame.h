// One frame of foveated sampling, prepared on the host before the frame and read-only
// while devices render it: the pattern shifted to the frame's gaze and clipped to the
// screen, each pixel's k nearest samples (found with nanoflann's k-d tree), and each
// sample's radius of influence, so that a device given a rectangle finds exactly the
// samples its pixels need without knowing who renders the rest.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "render/foveated_pattern.h"
#include "util/rect.h"

namespace multiray {

struct FoveationFrame {
  static constexpr uint32_t kNoSample = 0xffffffffu;

  int width = 0, height = 0;
  int k = 0;  // neighbours per pixel
  Vec2 gaze;  // pixels

  // The samples on screen, ordered by selection cell (row-major), so that the samples of a
  // rect are close in memory and their rays coherent. position: image position in pixels
  // (x right, y down) in [0, width] x [0, height]; id: index in the pattern, the key of the
  // sample's
  // random numbers; radius2: squared distance from the sample to the farthest pixel centre
  // that has it among its k nearest, -1 when no pixel does (such a sample is never
  // rendered).
  std::vector<Vec2> position;
  std::vector<uint32_t> id;
  std::vector<float> radius2;

  // k sample indices (into `position`) per pixel, row-major, nearest first; padded with
  // kNoSample when the screen holds fewer than k samples. Never all kNoSample: the sample
  // at the gaze is always on screen.
  std::vector<uint32_t> neighbours;
  // The reconstruction weights of those neighbours, k per pixel, summing to 1 (0 for
  // padding): inverse squared distance to the pixel centre (Shepard's interpolation),
  // normalised. A sample within 1e-6 pixels of the centre is moved to the front of the list
  // and gets weight 1, the others 0.
  std::vector<float> weights;

  // Per pixel, the used samples (radius2 >= 0) whose position falls inside it: the frame's
  // cost map for balancers that split by samples. Sums to used_samples.
  std::vector<float> pixel_samples;
  uint64_t used_samples = 0;

  // Used samples bucketed by position in cells of cell_px x cell_px pixels (CSR), and the
  // largest radius rounded up: a rectangle's samples lie within `reach` of it.
  int cell_px = 16, cells_x = 0, cells_y = 0;
  std::vector<uint32_t> cell_start, cell_samples;
  float reach = 0;

  size_t size() const { return position.size(); }
  // The selection cell holding image position `p` (inside the closed screen).
  size_t cell_of(Vec2 p) const {
    const int cx = std::min(int(p.x), width - 1) / cell_px;
    const int cy = std::min(int(p.y), height - 1) / cell_px;
    return size_t(cy) * size_t(cells_x) + size_t(cx);
  }
  const uint32_t* neighbours_of(int x, int y) const {
    return neighbours.data() + (size_t(y) * size_t(width) + size_t(x)) * size_t(k);
  }
  const float* weights_of(int x, int y) const {
    return weights.data() + (size_t(y) * size_t(width) + size_t(x)) * size_t(k);
  }
};

// Shifts `pattern` to the gaze (normalised screen coordinates, clamped to [0, 1]; (0, 0)
// is the top-left corner), clips it and builds the per-pixel neighbour lists, weights and
// radii.
// Pure function of its arguments; uses oneTBB for the neighbour queries.
FoveationFrame prepare_foveation_frame(const FoveationPattern& pattern, float gaze_x,
                                       float gaze_y);

// Indices of the samples whose disc (radius sqrt(radius2)) reaches a pixel centre of
// `rect`, ascending. Contract (the radius rule): it contains every sample in the
// neighbour list of every pixel of `rect`, so the rect can be reconstructed from them.
std::vector<uint32_t> select_samples(const FoveationFrame& f, Rect rect);

// The frame's used samples positioned inside `rect` (the sum of pixel_samples over it):
// the rect's share of the frame's work in the units balancers split by.
uint64_t samples_in_rect(const FoveationFrame& f, Rect rect);

// Squared distance from `p` to the box [x0, x1] x [y0, y1] (0 inside). The radii and the
// selection both use this one function (a pixel centre is a box with x0 = x1, y0 = y1):
// since rounding is monotone, a box containing a pixel centre is never found farther
// from a sample than the centre itself, so the radius rule holds in floating point too.
float distance2_to_box(Vec2 p, float x0, float y0, float x1, float y1);

}  // namespace multiray
