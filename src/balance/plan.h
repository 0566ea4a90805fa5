// What a frame asks for (FrameShape) and how a balancer says it should be split (Plan).
// Plain structs: the engine, the simulator and other renderers all read them the same way.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "balance/participation.h"
#include "partition/rect.h"

namespace multiray::balance {

// What is to be rendered this frame: `views` images of width×height pixels.
//
// `pixel_weight` is empty (every pixel costs the same) or holds the work of every pixel of
// every view, views·height·width values, row-major per view, views in order: samples per
// pixel under irregular sampling (adaptive edge samples, foveated patterns), or predicted
// volume samples per pixel (the volume raycaster's cost prediction). Balancers that split
// by work (semi-static, hybrid, bruder) split by these weights; the others split by area.
//
// `device_cost`, when not empty, holds per device a prediction of its cost in ms per unit
// of pixel weight for this frame (Bruder et al. 2017: sigma_i, learned by the renderer
// from features of the frame); balancers that use predictions (bruder) split by it, the
// others ignore it. Entries that are not finite and > 0 mean "no prediction".
struct FrameShape {
  int width = 0, height = 0, views = 1;
  std::vector<float> pixel_weight;
  std::vector<double> device_cost =
      {};  // (an initializer: FrameShape{w, h, v, {}} stays warning-free)

  int64_t pixels_per_view() const { return width > 0 && height > 0 ? int64_t(width) * height : 0; }
  int64_t pixels() const { return views > 0 ? pixels_per_view() * views : 0; }
  bool weighted() const { return !pixel_weight.empty(); }
  // True when the two shapes have the same size and view count (weights may differ).
  bool same_size(const FrameShape& o) const {
    return width == o.width && height == o.height && views == o.views;
  }
};

// Throws std::invalid_argument (one line) if `shape` has a negative size, views < 1, or
// a pixel_weight that is neither empty nor views·height·width long.
void validate_shape(const FrameShape& shape);

// How well to render a frame (frame-time targeting, Bruder et al. 2017): the engine renders
// every view at `image_scale` of the output size (the plan's items then cover
// scaled_shape(shape, image_scale)) and upsamples to the output; kernels that march along
// rays take `step_scale` times the user's step. 1 and 1 is full quality.
struct Quality {
  double image_scale = 1.0;  // (0, 1]
  double step_scale = 1.0;   // > 0
};

// `shape` rendered at `image_scale` in (0, 1]: each side max(1, round(side · scale)); the
// pixel weights, if any, taken from the nearest full-size pixel. Throws
// std::invalid_argument for a scale outside (0, 1].
FrameShape scaled_shape(const FrameShape& shape, double image_scale);

// The plan for one frame.
//
// Dispatch semantics (the engine implements exactly this; simulate() models it): each
// device first takes the items of assigned[i] in order; then pulls `batch` items at a
// time from the front of `shared` (pulled items become its own, not yet started); then,
// if `steal`, repeatedly takes the LAST not-started item of the device with the most
// not-started work (pixels × weight, > 0; the lowest index on ties). All items together cover
// every pixel of every view exactly once.
struct Plan {
  std::vector<std::vector<WorkItem>> assigned;  // per device, in order
  std::vector<WorkItem> shared;                 // pulled on demand, front first
  int batch = 1;                                // items per pull from `shared`, >= 1
  bool steal = false;
  std::vector<double> ratios;  // intended share of the frame's work per device, sum 1
  Quality quality;             // items cover scaled_shape(shape, quality.image_scale)
  // How a device behind a link (a worker rank) is sent the items it pulls or steals: true,
  // one at a time, the next only once it reports the last one rendered, whose pixels
  // upload meanwhile (Seo et al.'s strategy I); false, kept several deep at the device so
  // that the round trip hides (multiray's own, --depth). Local devices ignore it.
  bool pull_on_ready = false;
  // Devices left out of this frame (balance/participation.h): resting[i] set means device
  // i has no items, is not started, pulls and steals nothing and costs nothing; the
  // engine does not wait for it. Empty: every device takes part. rest_reason[i] says why
  // in one line ("75 ms fixed per frame against a 44 ms frame").
  std::vector<bool> resting;
  std::vector<std::string> rest_reason;
  // Devices that take no part in stealing (with `steal` set): a device whose fixed cost
  // per launch outlasts the small items at a frame's end would make the frame wait by
  // taking one. Empty: every device may steal.
  std::vector<bool> no_steal;
  // The balancer's cost model of each device, when it keeps one (hybrid): for stats.json
  // and the trace. Empty otherwise.
  std::vector<DeviceCostModel> models;

  bool rests(size_t device) const { return device < resting.size() && resting[device]; }

  // Every item of the plan, device by device and then the shared queue.
  std::vector<WorkItem> all_items() const;
};

// Empty if `plan` is well formed for `shape` and `device_count` devices: one list and
// one ratio per device, finite non-negative ratios summing to 1 (or all 0 for a plan with
// no work: no device left, or no pixels), batch >= 1, a valid quality, and exact coverage
// of every pixel of the shape at the plan's image scale, no item inverted
// (coverage_error()). Otherwise one line saying what is wrong. O(n log n) in the items.
std::string check_plan(const Plan& plan, const FrameShape& shape, int device_count);

}  // namespace multiray::balance
