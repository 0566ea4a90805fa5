#include "app/viewer/view_denoise.h"

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

DenoiseMethod ViewDenoise::session_method(bool alone) const {
  if (!alone) return DenoiseMethod::none;  // a still camera's image is filtered in shown()
  return resolve_denoise(choice(), DenoiseContext{.viewer = true, .camera_moving = true});
}

std::shared_ptr<const Framebuffer> ViewDenoise::shown(const FrameResult& r, size_t view,
                                                      const Framebuffer& refined, int spp,
                                                      bool restarted, DenoiseMethod* used) {
  // The session filtered this frame: it was begun to be shown alone.
  if (view < r.denoised.size() && r.denoised_with != DenoiseMethod::none) {
    held_.reset();
    *used = r.denoised_with;
    return std::make_shared<const Framebuffer>(r.denoised[view]);
  }
  const DenoiseMethod method =
      resolve_denoise(choice(), DenoiseContext{.viewer = true, .spp = spp});
  if (method == DenoiseMethod::none || refined.features.empty()) {
    held_.reset();
    *used = DenoiseMethod::none;
    return std::make_shared<const Framebuffer>(refined);
  }
  *used = DenoiseMethod::atrous;
  // A converged image stands (the same samples): filtered once.
  if (held_ && !restarted && spp == held_spp_) return held_;
  auto out = std::make_shared<Framebuffer>();
  still_.apply_view(0, refined, nullptr, *out);
  held_ = out;
  held_spp_ = spp;
  return held_;
}

}  // namespace multiray::app::viewer
