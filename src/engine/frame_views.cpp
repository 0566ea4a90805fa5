#include "engine/frame_views.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/clock.h"
#include "render/gbuffer.h"

namespace multiray {

Vec2 GazePath::at(int frame) const {
  const float a = 2.0f * kPi * float(frame) / period;
  return Vec2{std::clamp(center.x + radius * std::cos(a), 0.0f, 1.0f),
              std::clamp(center.y + radius * std::sin(a), 0.0f, 1.0f)};
}

FrameViews::FrameViews(CameraRig rig, int width, int height, SamplingSetup sampling,
                       const RenderScene* host)
    : rig_(rig), width_(width), height_(height), sampling_(std::move(sampling)), host_(host) {
  if (sampling_.mode == Sampling::Adaptive && !host_)
    throw std::invalid_argument("adaptive sampling needs the scene for its edge pass");
  if (sampling_.mode == Sampling::Foveated && !sampling_.pattern)
    throw std::invalid_argument("foveated sampling needs a sample pattern");
}

FrameInput FrameViews::make(int frame, const Camera& camera) const {
  FrameInput in;
  for (const Camera& cam : rig_.views(camera)) {
    ViewSetup v;
    v.camera = cam;
    v.width = width_;
    v.height = height_;
    v.view = uint32_t(in.views.size());
    v.frame = uint32_t(frame);
    in.views.push_back(v);
  }
  const Stopwatch clock;
  if (sampling_.mode == Sampling::Adaptive) {
    for (const ViewSetup& v : in.views)
      in.maps.push_back(
          edge_sample_map(detect_edges(render_gbuffer(*host_, v)), sampling_.edge_spp, 1));
    for (size_t i = 0; i < in.views.size(); ++i) in.views[i].spp_map = &in.maps[i];
  } else if (sampling_.mode == Sampling::Foveated) {
    // One set-up serves every view: they share the image size and the gaze.
    const Vec2 g = sampling_.gaze.at(frame);
    in.foveation = std::make_shared<const FoveationFrame>(
        prepare_foveation_frame(*sampling_.pattern, g.x, g.y));
    for (ViewSetup& v : in.views) v.foveation = in.foveation.get();
  }
  if (sampling_.mode != Sampling::Uniform) in.sampling_ms = clock.elapsed_ms();
  return in;
}

}  // namespace multiray
