// The simplest kernel: the distance along the primary ray through each pixel's centre to
// the first surface (0 where the ray leaves the scene), as a grey value in scene units.
// One ray per pixel whatever the spp; no random numbers. Useful as a debugging view and as
// proof that the kernel seam carries something that is not the path tracer.
#pragma once

#include "render/kernel.h"

namespace multiray {

class DepthKernel : public Kernel {
 public:
  explicit DepthKernel(const RenderScene& rs) : rs_(rs) {}
  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out) const override;
  KernelStats render_samples(const ViewSetup& view, const RenderSettings& settings,
                             const ImageSample* samples, size_t n, Vec3* values) const override;

 private:
  const RenderScene& rs_;
};

}  // namespace multiray
