// The denoiser in the frame loop (issue 52): after the gather, on the master, each view's
// beauty is filtered with its feature buffers (render/denoise.h). The filter is a pure
// function of the whole frame, so the denoised image does not depend on how the frame was
// split. svgf keeps a history per view between frames; a view without feature buffers (a
// frame that could not record them) is passed through and its history dropped.
#pragma once

#include <vector>

#include "core/image.h"
#include "render/denoise.h"
#include "render/render_settings.h"

namespace multiray {

class FrameDenoiser {
 public:
  explicit FrameDenoiser(DenoiseMethod method, const DenoiseParams& params = {})
      : method_(method), params_(params) {}
  DenoiseMethod method() const { return method_; }

  // Writes one image per view to `out` (each the size of its beauty; no alpha, no
  // features) and returns the filter's wall time, ms. `views` give svgf its cameras.
  double apply(const std::vector<ViewSetup>& views, const std::vector<Framebuffer>& images,
               std::vector<Framebuffer>& out);
  // The same for views rendered smaller than the output (the plan's image scale under 1,
  // Engine::scaled_images): each is filtered at the size it was rendered (a quarter of the
  // taps at half scale; svgf's history then lives at that size) and the denoised image
  // enlarged to `width` x `height` (core/resample.h upscale_bilinear), instead of the
  // enlarged frame filtered at the output size. The time covers both.
  double apply_scaled(const std::vector<ViewSetup>& views, const std::vector<Framebuffer>& scaled,
                      int width, int height, std::vector<Framebuffer>& out);
  // The same for one image, view `view`'s (its history); `camera`: svgf's, or null.
  void apply_view(size_t view, const Framebuffer& image, const Camera* camera, Framebuffer& out);
  // Forgets every view's history (a new scene, a cut in the camera path).
  void reset() { states_.clear(); }

 private:
  DenoiseMethod method_;
  DenoiseParams params_;
  std::vector<DenoiseState> states_;  // per view
  std::vector<float> beauty_, result_;
  std::vector<Framebuffer> small_;  // apply_scaled's denoised images before enlarging
  DenoiseBuffers buffers_;          // the filter's, reused by every view and frame
};

}  // namespace multiray
