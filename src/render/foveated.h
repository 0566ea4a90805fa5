// Foveated sampling on a device (Harada & Fujita 2014; Harada, GPU Pro 7 ch. 4). The
// frame's samples are not tied to pixels: a device given a rectangle renders every
// sample whose disc of influence reaches the rectangle (select_samples), with the
// ordinary integrators, and then reconstructs each pixel from its k nearest samples.
// Samples on the border of two rectangles are rendered by both devices, from the same
// random numbers, so they get the same value and the image does not depend on the split.
#pragma once

#include <vector>

#include "core/image.h"
#include "render/foveation_frame.h"
#include "render/kernel.h"
#include "util/rect.h"

namespace multiray {

// The view's foveation data. Throws std::invalid_argument when there is none or it was
// prepared for another image size (a device reports that as a failed frame).
const FoveationFrame& foveation_of(const ViewSetup& view);

class FoveatedKernel {
 public:
  // `sampled` renders the samples (a kernel with KernelEntry::point_samples); it must
  // outlive this object.
  explicit FoveatedKernel(const Kernel& sampled) : sampled_(sampled) {}

  // Renders samples `idx[0..n)` of `*view.foveation` with the sampled kernel and writes sample s's
  // value to values[s] (`values` holds at least view.foveation->size() entries). Sample s is a
  // camera ray through position[s] with random numbers keyed by id[s]. Safe to call concurrently
  // for disjoint index lists.
  KernelStats shade(const ViewSetup& view, const RenderSettings& settings, const uint32_t* idx,
                    size_t n, Vec3* values) const;

  // The whole job for `rect` on the calling thread: select, shade, reconstruct into `out`
  // (the view's full-size image). `scratch` is resized to the frame's sample count.
  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out, std::vector<Vec3>& scratch) const;

 private:
  const Kernel& sampled_;
};

// Writes every pixel of `rect` into `out`: the weighted mean of the values of its k
// nearest samples, with the frame's weights (`values` indexed like f.position). Reads
// only the values of those neighbours, which select_samples(f, rect) contains. The mean
// is taken as v0 + Σ_{j>0} w_j (v_j - v0), v0 the nearest sample's value: mathematically
// Σ w_j v_j since the weights sum to 1, but exactly v0 when all neighbours agree, so a
// constant image reconstructs exactly whatever the rounding of the weights.
void reconstruct_rect(const FoveationFrame& f, const Vec3* values, Rect rect, Framebuffer& out);

}  // namespace multiray
