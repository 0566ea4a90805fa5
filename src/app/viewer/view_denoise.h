// The live viewer's denoiser (issue 52: "the viewer has a denoise toggle"; `auto`: on in
// `view` while the camera moves). The page chooses none, atrous, svgf or auto (the
// "denoise" message of view_control.h; `view --denoise` the choice to start with), and
// this decides, frame by frame, what filters the image the page is shown:
// - A frame shown alone (the camera moved, so the refinement starts again from it, or it
//   was rendered smaller while the camera moves): the session's denoiser filters it after
//   the gather (Session::set_denoise, FrameResult::denoised), svgf with its history across
//   the moving frames; a frame rendered smaller at the size it was rendered, the denoised
//   image then enlarged (FrameDenoiser::apply_scaled).
// - A still camera's refined image (engine/refinement.h: the mean of the frames since it
//   stopped, with their feature buffers pooled): the à-trous filter here, spatial only,
//   for svgf too: the refinement is the exact temporal accumulation (one camera, every
//   sample weighed alike) that svgf's history approximates, and svgf's bookkeeping of
//   independent frames would be wrong for means that share their samples. Once the image
//   has converged it is filtered once and held. Meanwhile the session filters nothing.
// So the session's method switches when the camera starts and stops moving, and svgf's
// history starts again with each move (Session::set_denoise). auto is svgf while the
// camera moves and while the still image has under 256 samples per pixel, then the
// refined image as it is (resolve_denoise), with one more rule of its own: a moving frame
// is filtered only while the filter costs at most kMovingShare of a moving frame's time
// (issue 52's goal: the frame rate with svgf within 15% of the raw one). The cost is
// learnt from every filtering here (ms per pixel) and the moving frames' engine time; the
// first moving frame is filtered to measure it (per pixel filtered: a moving frame's are
// those it was rendered at). On two CPU cores the filter takes ~55-65 ms at 640x360, ~19 ms
// (svgf) for a half-scale moving frame, against a ~14-19 ms raw frame (docs/noise.md,
// measured 2026-12-04; the session filters a moving frame while the next renders, which
// on shared cores saves nothing), so `auto` mostly shows raw frames while the camera moves, and
// filters the still image only while the filter has been idle for at least (1 - kMovingShare) of
// the time, holding the last filtered image in between; a choice of svgf or atrous by name is
// always followed.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "core/image.h"
#include "engine/frame_denoiser.h"
#include "engine/session.h"

namespace multiray::app::viewer {

// The `--denoise` name of a choice or a method ("none", "atrous", "svgf", "auto").
std::string denoise_name(DenoiseChoice choice);
std::string denoise_name(DenoiseMethod method);

class ViewDenoise {
 public:
  explicit ViewDenoise(DenoiseChoice choice) : choice_(choice) {}

  // The page's choice; thread-safe (the server's threads set it, the session's read it).
  void choose(DenoiseChoice choice) { choice_ = choice; }
  DenoiseChoice choice() const { return choice_.load(); }

  // Before a frame, on the session's thread: the method the session's denoiser runs on it
  // (none unless the frame is to be shown `alone`).
  DenoiseMethod session_method(bool alone) const;

  // The image to show of view `view` of frame `r`, whose refined image is `refined` with
  // `spp` samples per pixel (the frame itself when the refinement `restarted` with it).
  // `*used` is the filter that made it (none: `refined` as it is). On the session's thread.
  std::shared_ptr<const Framebuffer> shown(const FrameResult& r, size_t view,
                                           const Framebuffer& refined, int spp, bool restarted,
                                           DenoiseMethod* used);

 private:
  // The largest share of a moving frame's time `auto` lets the filter take.
  static constexpr double kMovingShare = 0.15;
  // auto, and the filter would take more than kMovingShare of a moving frame's time.
  bool too_dear() const;
  // Learns the filter's cost per pixel from one filtering of `pixels` in `ms`.
  void learn_cost(double ms, size_t pixels);

  std::atomic<DenoiseChoice> choice_;
  // What auto's cost rule knows, written and read on the session's thread: the filter's
  // ms per pixel filtered, a moving frame's engine time and the pixels the session filters
  // of it, those it was rendered at (< 0: unknown).
  double ms_per_pixel_ = -1, moving_frame_ms_ = -1, pixels_ = -1;
  // When the still image was filtered last, and how long that took.
  std::chrono::steady_clock::time_point filtered_at_{};
  double last_filter_ms_ = 0;
  FrameDenoiser still_{DenoiseMethod::atrous};
  std::shared_ptr<const Framebuffer> held_;  // the refined image last filtered, or null
  int held_spp_ = 0;
};

}  // namespace multiray::app::viewer
