// The prediction seam (Bruder, Frey & Ertl 2017, §4–5): before each frame an advisor may
// predict the work of every pixel and each device's cost per unit of that work, and choose
// the frame's quality (frame-time targeting); after the frame it is told what was
// measured, to learn. The engine hands the predictions to the balancer through
// FrameShape::pixel_weight and FrameShape::device_cost, and renders at the advised
// quality. A renderer-specific model (volume/volume_advisor.h) lives behind it; balancers
// stay pure policy over the numbers.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "balance/plan.h"
#include "balance/stats.h"
#include "engine/frame_record.h"
#include "render/render_types.h"

namespace multiray {

struct FrameAdvice {
  balance::Quality quality;         // what to render the frame at; {1, 1} is full quality
  std::vector<float> pixel_work;    // predicted work per output pixel (views·h·w), or empty
  std::vector<double> device_cost;  // predicted ms per unit of work per device, or empty
  double predicted_ms = 0;          // the advisor's frame-time prediction at `quality` (0: none)
  double advise_ms = 0;             // time the advisor took (set by the engine)
};

class FrameAdvisor {
 public:
  virtual ~FrameAdvisor() = default;
  // Called by the engine before `frame` is planned; `views` at the output size.
  virtual FrameAdvice advise(int frame, const std::vector<ViewSetup>& views,
                             const RenderSettings& settings) = 0;
  // Called after the frame with what the devices measured; `advice` is what advise()
  // returned for it.
  virtual void measured(const FrameAdvice& advice, const FrameRecord& record,
                        const balance::FrameStats& stats) = 0;
  // Two-pass frame-time targeting: after the first pass of a frame (`first` as advised,
  // `first_pass` as measured), the advice for a second pass over the same views that
  // replaces the first pass's image, or none when the first pass is the frame. Called
  // before measured(), which then sees the pass that became the frame. Default: none.
  virtual std::optional<FrameAdvice> second_pass(const FrameAdvice& /*first*/,
                                                 const FrameRecord& /*first_pass*/) {
    return std::nullopt;
  }
  // After measured(): adds what the advisor knows about the frame to its record (e.g. each
  // device's predicted and measured cost). Default: nothing.
  virtual void annotate(FrameRecord& /*record*/) const {}
};

}  // namespace multiray
