#include "engine/frame_denoiser.h"

#include <cstring>

#include "core/clock.h"
#include "core/resample.h"

namespace multiray {

double FrameDenoiser::apply(const std::vector<ViewSetup>& views,
                            const std::vector<Framebuffer>& images,
                            std::vector<Framebuffer>& out) {
  Stopwatch clock;
  out.resize(images.size());
  for (size_t v = 0; v < images.size(); ++v)
    apply_view(v, images[v], v < views.size() ? &views[v].camera : nullptr, out[v]);
  return clock.elapsed_ms();
}

double FrameDenoiser::apply_scaled(const std::vector<ViewSetup>& views,
                                   const std::vector<Framebuffer>& scaled, int width, int height,
                                   std::vector<Framebuffer>& out) {
  Stopwatch clock;
  apply(views, scaled, small_);
  out.resize(small_.size());
  for (size_t v = 0; v < small_.size(); ++v) {
    if (out[v].width != width || out[v].height != height) out[v] = Framebuffer(width, height);
    upscale_bilinear(small_[v], out[v]);
  }
  return clock.elapsed_ms();
}

void FrameDenoiser::apply_view(size_t view, const Framebuffer& image, const Camera* camera,
                               Framebuffer& o) {
  if (states_.size() <= view) states_.resize(view + 1);
  o.width = image.width, o.height = image.height;
  o.pixels.resize(image.pixels.size());
  o.alpha.clear(), o.features.clear();
  const FeatureBuffers& f = image.features;
  if (method_ == DenoiseMethod::none || f.empty() || f.width != image.width ||
      f.height != image.height) {
    o.pixels = image.pixels;
    states_[view].reset();
    return;
  }
  const size_t n = image.pixels.size();
  beauty_.resize(3 * n), result_.resize(3 * n);
  for (size_t i = 0; i < n; ++i)
    beauty_[3 * i] = image.pixels[i].x, beauty_[3 * i + 1] = image.pixels[i].y,
                beauty_[3 * i + 2] = image.pixels[i].z;
  DenoiseInput in;
  in.width = image.width, in.height = image.height;
  in.beauty = beauty_.data();
  in.albedo = f.albedo.data(), in.normal = f.normal.data(), in.depth = f.depth.data();
  in.variance = f.variance.empty() ? nullptr : f.variance.data();
  in.emission = f.emission.empty() ? nullptr : f.emission.data();
  in.camera = camera;
  denoise(in, method_, &states_[view], result_.data(), params_, &buffers_);
  for (size_t i = 0; i < n; ++i)
    o.pixels[i] = {result_[3 * i], result_[3 * i + 1], result_[3 * i + 2]};
}

}  // namespace multiray
