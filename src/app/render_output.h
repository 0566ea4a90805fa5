// What `render` does with each finished frame: writes its images (PNG, EXR, quilt) where
// the OutputTarget says, prints its line, keeps its JSON record on disk (FrameSpool: memory
// stays flat however many frames) and, with --trace, its per-item measurements.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/frame_spool.h"
#include "app/output_target.h"
#include "core/composite.h"
#include "core/image.h"
#include "engine/session.h"
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
  // With frame-time targeting: warn once when a frame's quality drops past what shows
  // (study/adapt_summary.h degraded_quality_warning).
  void set_target_ms(double target_ms) { target_ms_ = target_ms; }
  // Augmented reality: images with an alpha channel are written as an RGBA layer
  // (<name>_rgba.png, and .exr with --exr) and, as the main image, composited over these
  // real images (core/composite.h); without them, over black.
  void set_background(std::shared_ptr<const BackgroundImages> b) { background_ = std::move(b); }

  const RenderCounters& counters() const { return counters_; }
  // The exposure the PNG files were written with (metered or given), in stops; the metered
  // value is known once a frame has arrived.
  float exposure_ev() const { return display_.exposure_ev; }
  bool metered() const { return !fixed_exposure_ && metered_; }

  // Writes the stats file: `head` with every frame's record as "frames".
  void write_stats(const nlohmann::json& head) { records_.write(target_.stats_path(), head); }

 private:
  void write_images(const FrameResult& r);

  OutputTarget target_;
  FrameSpool records_;
  RenderCounters counters_;
  bool fixed_exposure_, metered_ = false, quiet_, warned_quality_ = false;
  double target_ms_ = 0;
  int columns_;
  Display display_;
  study::TraceFile* trace_;
  std::shared_ptr<const BackgroundImages> background_;
};

}  // namespace multiray::app
