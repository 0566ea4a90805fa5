#include "app/viewer/motion.h"

namespace multiray::app::viewer {

bool MotionClock::moving(Clock::time_point at) const {
  const Clock::time_point last{Clock::duration(last_.load(std::memory_order_relaxed))};
  return at - last < std::chrono::duration<double>(kMotionHoldSeconds);
}

FrameAdvice MotionAdvisor::advise(int, const std::vector<ViewSetup>&, const RenderSettings&) {
  FrameAdvice advice;
  if (clock_->moving()) advice.quality.image_scale = scale_;
  return advice;
}

}  // namespace multiray::app::viewer
