// Cheaper frames while the camera moves (issue 33, "interactive at any frame rate"): while
// the page has moved the camera within the last kMotionHoldSeconds, frames are rendered at
// a reduced image scale (fewer pixels, upsampled by the engine, as frame-time targeting
// does in image space), and at full size once it stands, where engine/refinement.h then refines
// them. The advisor is the engine's quality seam (engine/frame_advisor.h), so every
// balancer sees the smaller frame as it would any other.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>

#include "engine/frame_advisor.h"

namespace multiray::app::viewer {

// A move counts as ongoing this long after the last camera message: a page sends at
// most one a display frame (60 Hz) while the mouse drags.
constexpr double kMotionHoldSeconds = 0.15;

// When the camera last moved; written by the server's threads, read by the session's.
class MotionClock {
 public:
  using Clock = std::chrono::steady_clock;
  void moved(Clock::time_point at = Clock::now()) {
    last_.store(at.time_since_epoch().count(), std::memory_order_relaxed);
  }
  // Whether a move happened within kMotionHoldSeconds before `at`.
  bool moving(Clock::time_point at = Clock::now()) const;

 private:
  std::atomic<int64_t> last_{INT64_MIN / 2};  // Clock ticks; long ago
};

// Advises `scale` (in (0, 1]) as the image scale of frames begun while the camera moves,
// full quality otherwise.
class MotionAdvisor : public FrameAdvisor {
 public:
  MotionAdvisor(std::shared_ptr<const MotionClock> clock, double scale)
      : clock_(std::move(clock)), scale_(scale) {}
  FrameAdvice advise(int frame, const std::vector<ViewSetup>& views,
                     const RenderSettings& settings) override;
  void measured(const FrameAdvice&, const FrameRecord&, const balance::FrameStats&) override {}

 private:
  std::shared_ptr<const MotionClock> clock_;
  double scale_;
};

}  // namespace multiray::app::viewer
