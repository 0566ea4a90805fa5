// Direct illumination: emission seen from the camera plus the light arriving at the first
// surface straight from the lights, by one light sample and one BSDF sample combined with
// multiple importance sampling (Veach 1997). It is the path tracer stopped after one
// bounce, so both share every other choice (materials, lights, random numbers); Harada's
// foveated-rendering experiments use it (GPU Pro 7, ch. 4, Fig. 4.4). CPU devices only.
#pragma once

#include "render/path_tracer.h"

namespace multiray {

class DirectLighting : public Kernel {
 public:
  explicit DirectLighting(const RenderScene& rs) : path_(rs) {}

  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out) const override {
    return path_.render_rect(view, one_bounce(settings), rect, out);
  }
  KernelStats render_samples(const ViewSetup& view, const RenderSettings& settings,
                             const ImageSample* samples, size_t n, Vec3* radiance) const override {
    return path_.render_samples(view, one_bounce(settings), samples, n, radiance);
  }

 private:
  static RenderSettings one_bounce(RenderSettings s) {
    s.max_bounces = 1;
    return s;
  }
  PathTracer path_;
};

}  // namespace multiray
