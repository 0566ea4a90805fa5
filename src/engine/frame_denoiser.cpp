#include "engine/frame_denoiser.h"

#include <cstring>

#include "core/clock.h"

namespace multiray {

double FrameDenoiser::apply(const std::vector<ViewSetup>& views,
                            const std::vector<Framebuffer>& images,
                            std::vector<Framebuffer>& out) {
  Stopwatch clock;
  out.resize(images.size());
  states_.resize(images.size());
  for (size_t v = 0; v < images.size(); ++v) {
    const Framebuffer& image = images[v];
    Framebuffer& o = out[v];
    o.width = image.width, o.height = image.height;
    o.pixels.resize(image.pixels.size());
    o.alpha.clear(), o.features.clear();
    const FeatureBuffers& f = image.features;
    if (method_ == DenoiseMethod::none || f.empty() || f.width != image.width ||
        f.height != image.height) {
      o.pixels = image.pixels;
      states_[v].reset();
      continue;
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
    in.camera = v < views.size() ? &views[v].camera : nullptr;
    denoise(in, method_, &states_[v], result_.data(), {}, &buffers_);
    for (size_t i = 0; i < n; ++i)
      o.pixels[i] = {result_[3 * i], result_[3 * i + 1], result_[3 * i + 2]};
  }
  return clock.elapsed_ms();
}

}  // namespace multiray
