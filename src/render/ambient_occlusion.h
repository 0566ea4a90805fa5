// Ambient occlusion, the integrator of Harada's irregular-sampling experiments (GPU Pro 7
// ch. 4: adaptive edge sampling, after Mitchell 1987): per sample, one primary ray and `ao_rays`
// cosine-distributed occlusion rays of length `ao_distance` from the hit; the pixel value is the
// unoccluded fraction (1 where the primary ray leaves the scene). Random numbers as in the path
// tracer, from (pixel, sample, frame, view), so images do not depend on the split.
#pragma once

#include "core/image.h"
#include "render/kernel.h"
#include "render/render_types.h"
#include "util/rect.h"

namespace multiray {

class Rng;

class AmbientOcclusion : public Kernel {
 public:
  explicit AmbientOcclusion(const RenderScene& rs);

  // Renders every pixel of `rect` (the view's sample map or settings.spp samples each)
  // into `out`. Safe to call concurrently for disjoint rectangles.
  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out) const override;

  // One AO sample through each of `samples[0..n)` (the position is the sample, no jitter),
  // its unoccluded fraction written to `value[i]` (grey). Random numbers from
  // (key, 0, frame, view, seed). Safe to call concurrently.
  KernelStats render_samples(const ViewSetup& view, const RenderSettings& settings,
                             const ImageSample* samples, size_t n, Vec3* value) const override;

 private:
  // The unoccluded fraction seen along `primary`, drawing the occlusion rays from `rng`.
  float occlusion(const Ray& primary, Rng& rng, const RenderSettings& settings,
                  KernelStats& stats) const;

  const RenderScene& rs_;
  float eps_;            // ray-origin offset, scaled to the scene
  float default_range_;  // 0.3 of the scene's largest extent
};

}  // namespace multiray
