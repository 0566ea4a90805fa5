// What `render` does with each finished frame: writes its images (PNG, EXR, quilt) where
// the OutputTarget says, prints its line, keeps its JSON record on disk (FrameSpool: memory
// stays flat however many frames) and, with --trace, its per-item measurements.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/frame_spool.h"
#include "app/output_target.h"
#include "core/composite.h"
#include "core/image.h"
#include "engine/session.h"
#include "study/adapt_summary.h"
#include "study/trace_file.h"

namespace multiray::app {

// What the progress line reads while frames finish.
struct RenderCounters {
  std::atomic<int> frames{0};
  std::atomic<uint64_t> samples{0};
  std::atomic<uint64_t> frame_us{0};  // the finished frames' times, microseconds
};

class RenderOutput : public FrameObserver {
 public:
  // `display.exposure_ev` is used as given when `fixed_exposure`; otherwise the exposure is
  // metered on the first frame that arrives (core/exposure.h) and held for the rest of the
  // run, as a camera's exposure lock does, so an animation does not flicker.
  RenderOutput(OutputTarget target, bool fixed_exposure, bool quiet, int columns,
               const Display& display, study::TraceFile* trace);

  void on_frame(const std::shared_ptr<const FrameResult>& r) override;
  // With frame-time targeting: warn once when a frame's quality drops past what shows, with
  // the target that would keep it, fitted to the frames so far (study/adapt_summary.h
  // degraded_quality_warning); `lowest_cost` is the coarsest cost factor targeting may
  // choose (balance::lowest_cost).
  void set_targeting(double target_ms, double lowest_cost) {
    target_ms_ = target_ms, lowest_cost_ = lowest_cost;
  }
  // Augmented reality: images with an alpha channel are written as an RGBA layer
  // (<name>_rgba.png, and .exr with --exr) and, as the main image, composited over these
  // real images (core/composite.h); without them, over black.
  void set_background(std::shared_ptr<const BackgroundImages> b) { background_ = std::move(b); }

  // --aov: these feature buffers (core/feature_buffers.h aov_names()) are written as layers
  // of the frame's EXR, or without --exr of <name>_aov.exr beside the PNG. The frames must
  // carry them (RenderSettings::feature_buffers).
  void set_aovs(std::vector<std::string> aovs) { aovs_ = std::move(aovs); }
  // Frames with a denoised image (FrameResult::denoised) show it in their PNGs; their EXRs
  // hold it only when `on` (else the raw beauty, as rendered).
  void set_denoised_exr(bool on) { denoised_exr_ = on; }

  // The devices' names, in order (for the overlay's legend and the summary).
  void set_device_names(std::vector<std::string> names) { device_names_ = std::move(names); }
  // --overlay: beside each image, <name>_split.png, the frame with each device's pieces
  // tinted and a legend (study/split_overlay.h).
  void set_overlay() { overlay_ = true; }
  // The balance over the frames so far, a few lines for the end of the run: each device's
  // share of the samples and busy time a frame, and how closely they finished; with one
  // device, a line saying so ("" before any frame).
  std::string balance_summary() const;

  const RenderCounters& counters() const { return counters_; }
  // The exposure the PNG files were written with (metered or given), in stops; the metered
  // value is known once a frame has arrived.
  float exposure_ev() const { return display_.exposure_ev; }
  bool metered() const { return !fixed_exposure_ && metered_; }

  // Writes the stats file: `head` with every frame's record as "frames".
  void write_stats(const nlohmann::json& head) { records_.write(target_.stats_path(), head); }

 private:
  void write_images(const FrameResult& r);
  void write_overlay(const FrameResult& r, size_t view, const Framebuffer& image,
                     const std::string& tag);
  void add_to_summary(const FrameResult& r);

  OutputTarget target_;
  FrameSpool records_;
  RenderCounters counters_;
  bool fixed_exposure_, metered_ = false, quiet_, warned_quality_ = false;
  double target_ms_ = 0, lowest_cost_ = 0;
  std::vector<study::QualityTime> targeted_frames_;  // every frame's quality and time so far
  int columns_;
  Display display_;
  study::TraceFile* trace_;
  std::shared_ptr<const BackgroundImages> background_;
  bool overlay_ = false;
  std::vector<std::string> aovs_;
  bool denoised_exr_ = false;
  std::vector<std::string> device_names_;
  // The summary's sums over frames: per device samples, busy ms and frames taken part in.
  std::vector<double> sum_samples_, sum_busy_;
  std::vector<int> took_part_;
  double sum_imbalance_ = 0;
  int summary_frames_ = 0;
  std::string last_overlay_;  // the newest overlay's path
};

}  // namespace multiray::app
