#include "app/viewer/view_denoise.h"

#include <chrono>

#include "balance/plan.h"
#include "core/clock.h"

namespace multiray::app::viewer {

std::string denoise_name(DenoiseChoice choice) {
  for (const DenoiseMethodInfo& m : denoise_methods())
    if (m.choice == choice) return m.name;
  return "none";
}

std::string denoise_name(DenoiseMethod method) {
  return denoise_name(method == DenoiseMethod::svgf     ? DenoiseChoice::svgf
                      : method == DenoiseMethod::atrous ? DenoiseChoice::atrous
                                                        : DenoiseChoice::none);
}

namespace {

// The pixels the session's denoiser filtered of a frame whose view is `image`: the view's
// at the size it was rendered (the frame's image scale; FrameDenoiser::apply_scaled).
double filtered_pixels(const FrameResult& r, const Framebuffer& image) {
  balance::FrameShape shape;
  shape.width = image.width, shape.height = image.height, shape.views = 1;
  return double(balance::scaled_shape(shape, r.record.quality.image_scale).pixels());
}

}  // namespace

DenoiseMethod ViewDenoise::session_method(bool alone) const {
  if (!alone) return DenoiseMethod::none;      // a still camera's image is filtered in shown()
  if (too_dear()) return DenoiseMethod::none;  // the raw frame is shown (shown())
  return resolve_denoise(choice(), DenoiseContext{.viewer = true, .camera_moving = true});
}

bool ViewDenoise::too_dear() const {
  return choice() == DenoiseChoice::automatic && ms_per_pixel_ >= 0 && moving_frame_ms_ > 0 &&
         pixels_ > 0 && ms_per_pixel_ * pixels_ > kMovingShare * moving_frame_ms_;
}

void ViewDenoise::learn_cost(double ms, size_t pixels) {
  if (!(ms > 0) || pixels == 0) return;
  const double m = ms / double(pixels);
  ms_per_pixel_ = ms_per_pixel_ < 0 ? m : 0.5 * ms_per_pixel_ + 0.5 * m;
}

std::shared_ptr<const Framebuffer> ViewDenoise::shown(const FrameResult& r, size_t view,
                                                      const Framebuffer& refined, int spp,
                                                      bool restarted, DenoiseMethod* used) {
  if (restarted) {  // a frame shown alone: what a moving frame costs raw
    moving_frame_ms_ = r.record.frame_ms + r.record.gather_ms;
    pixels_ = filtered_pixels(r, refined);
  }
  // The session filtered this frame: it was begun to be shown alone.
  if (view < r.denoised.size() && r.denoised_with != DenoiseMethod::none) {
    learn_cost(r.record.denoise_ms / double(r.denoised.size()),
               size_t(filtered_pixels(r, r.denoised[view])));
    held_.reset();
    *used = r.denoised_with;
    return std::make_shared<const Framebuffer>(r.denoised[view]);
  }
  const DenoiseMethod method =
      resolve_denoise(choice(), DenoiseContext{.viewer = true, .spp = spp});
  // A frame shown alone that auto's cost rule left unfiltered stays raw here too.
  if (method == DenoiseMethod::none || refined.features.empty() || (restarted && too_dear())) {
    held_.reset();
    *used = DenoiseMethod::none;
    return std::make_shared<const Framebuffer>(refined);
  }
  *used = DenoiseMethod::atrous;
  // A converged image stands (the same samples): filtered once.
  if (held_ && !restarted && spp == held_spp_) return held_;
  // auto, the filter too dear: the image filtered last stands until the filter has been
  // idle kMovingShare of the time, so that refining goes on at nearly its raw pace.
  const double since =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - filtered_at_)
          .count();
  if (held_ && !restarted && too_dear() && since * kMovingShare < last_filter_ms_) return held_;
  auto out = std::make_shared<Framebuffer>();
  Stopwatch clock;
  still_.apply_view(0, refined, nullptr, *out);
  last_filter_ms_ = clock.elapsed_ms();
  filtered_at_ = std::chrono::steady_clock::now();
  learn_cost(last_filter_ms_, refined.pixels.size());
  held_ = out;
  held_spp_ = spp;
  return held_;
}

}  // namespace multiray::app::viewer
