#include "engine/frame_views.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

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
  if ((sampling_.mode == Sampling::Adaptive || sampling_.mode == Sampling::Reprojected) && !host_)
    throw std::invalid_argument("adaptive and reprojected sampling need the scene on the host");
  if (sampling_.mode == Sampling::Reprojected &&
      (sampling_.reproject_spp < 1 || sampling_.reproject_spp > 255))
    throw std::invalid_argument("reprojected sampling takes 1..255 samples per pixel");
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
  } else if (sampling_.mode == Sampling::Reprojected) {
    reproject(in);
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

void FrameViews::reproject(FrameInput& in) const {
  auto frame = std::make_shared<ReprojectedFrame>();
  frame->reference = uint32_t(rig_.centre_view());
  const ViewSetup& ref = in.views[frame->reference];
  const GBuffer depth = render_gbuffer(*host_, ref);
  const size_t n = in.views.size();
  frame->maps.resize(n);
  in.maps.resize(n);
  // Views in parallel: each writes only its own map.
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const ViewSetup& v = in.views[i];
    if (i == frame->reference) {
      in.maps[i].assign(size_t(v.width) * size_t(v.height), uint8_t(sampling_.reproject_spp));
    } else {
      frame->maps[i] = reproject_view(depth, ref, v);
      in.maps[i] = hole_sample_map(frame->maps[i], sampling_.reproject_spp);
    }
  });
  for (size_t i = 0; i < in.views.size(); ++i) in.views[i].spp_map = &in.maps[i];
  in.reprojection = std::move(frame);
}

}  // namespace multiray
