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

namespace {
// Each view is warped from this many references at most, the nearest: farther ones rarely
// add a pixel (a nearer one sees nearly all they see), and each costs a warp of the view.
constexpr size_t kNearestReferences = 4;
}  // namespace

void FrameViews::reproject(FrameInput& in) const {
  auto frame = std::make_shared<ReprojectedFrame>();
  for (int r : rig_.reference_views(sampling_.reference_spacing))
    frame->references.push_back(uint32_t(r));
  const size_t n = in.views.size(), refs = frame->references.size();
  std::vector<ReferenceSurface> surfaces(refs);
  for (size_t k = 0; k < refs; ++k) {
    const ViewSetup& ref = in.views[frame->references[k]];
    surfaces[k] = prepare_reference(render_gbuffer(*host_, ref), ref);
  }
  frame->maps.resize(n);
  in.maps.resize(n);
  // Views in parallel: each writes only its own map.
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const ViewSetup& v = in.views[i];
    if (frame->is_reference(i)) {
      in.maps[i].assign(size_t(v.width) * size_t(v.height), uint8_t(sampling_.reproject_spp));
      return;
    }
    // References nearest to this view first (a surface several of them see keeps the
    // nearest one's colour); the sources are renumbered to frame->references' order below.
    std::vector<size_t> order(refs);
    for (size_t k = 0; k < refs; ++k) order[k] = k;
    const auto distance = [&](size_t k) {
      return length(in.views[frame->references[k]].camera.eye - v.camera.eye);
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return distance(a) < distance(b); });
    order.resize(std::min(order.size(), kNearestReferences));
    std::vector<const ReferenceSurface*> by_distance;
    for (size_t k : order) by_distance.push_back(&surfaces[k]);
    ReprojectionMap m = reproject_view(by_distance, v);
    // Sources are numbered by position in by_distance; renumber to frame->references.
    const size_t pixels = m.source.size();
    for (int32_t& s : m.source)
      if (s != ReprojectionMap::kHole)
        s = int32_t(order[size_t(s) / pixels] * pixels + size_t(s) % pixels);
    frame->maps[i] = std::move(m);
    in.maps[i] = hole_sample_map(frame->maps[i], sampling_.reproject_spp);
  });
  for (size_t i = 0; i < n; ++i) in.views[i].spp_map = &in.maps[i];
  in.reprojection = std::move(frame);
}

}  // namespace multiray
