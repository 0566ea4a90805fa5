// A frame advisor for engine tests: every frame at half the output's width and height, as
// the viewer's while the camera moves.
#pragma once

#include <vector>

#include "engine/frame_advisor.h"

namespace multiray::testing {

struct HalfScale : FrameAdvisor {
  FrameAdvice advise(int, const std::vector<ViewSetup>&, const RenderSettings&) override {
    FrameAdvice a;
    a.quality.image_scale = 0.5;
    return a;
  }
  void measured(const FrameAdvice&, const FrameRecord&, const balance::FrameStats&) override {}
};

}  // namespace multiray::testing
