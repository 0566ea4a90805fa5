// What each frame renders: the views of the camera rig around the frame's camera, at the
// output size, with the sample maps irregular sampling needs (adaptive: a G-buffer pass
// finds edges; foveated: the pattern shifted to the frame's gaze, neighbours found). Runs
// on the host before the devices start; its time is reported apart from the frame time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/foveated_pattern.h"
#include "render/foveation_frame.h"
#include "render/render_types.h"
#include "render/reprojection.h"
#include "scene/camera_rig.h"

namespace multiray {

// Where the viewer looks in each frame, in normalised screen coordinates ((0,0) top left,
// (1,1) bottom right). A radius > 0 circles `center` at that radius, one turn every
// `period` frames, clamped to the screen: a slowly moving gaze.
struct GazePath {
  Vec2 center{0.5f, 0.5f};
  float radius = 0.0f;    // 0: the gaze stays at `center`
  float period = 100.0f;  // frames per turn
  Vec2 at(int frame) const;
};

// Reprojected: the centre view is path-traced and reprojected into the others, which
// path-trace only their holes (render/reprojection.h).
enum class Sampling { Uniform, Adaptive, Foveated, Reprojected };

struct SamplingSetup {
  Sampling mode = Sampling::Uniform;
  int edge_spp = 5;       // adaptive: samples of edge pixels (the others get 1)
  int reproject_spp = 1;  // reprojected: samples of the centre view and of holes, 1..255
  // Reprojected: references every this many views from the centre (CameraRig::
  // reference_views); 0: the centre view alone, as Leria et al.
  int reference_spacing = 0;
  GazePath gaze;                                    // foveated
  std::shared_ptr<const FoveationPattern> pattern;  // foveated: made once per run
};

// The views of one frame. `views` point into `maps` and `foveation`: keep the FrameInput
// alive while the frame renders.
struct FrameInput {
  std::vector<std::vector<uint8_t>> maps;
  std::shared_ptr<const FoveationFrame> foveation;       // shared by all views of the frame
  std::shared_ptr<const ReprojectedFrame> reprojection;  // reprojected sampling only
  std::vector<ViewSetup> views;
  double sampling_ms = 0;  // host time of the edge pass, foveation or reprojection set-up, ms

  // What the frame's rendered images still need: reprojected sampling fills every view
  // but the centre from the centre's image. Call after the devices rendered `images`.
  void finish(std::vector<Framebuffer>& images) const {
    if (reprojection) reprojection->fill(images);
  }
};

class FrameViews {
 public:
  // `host` (the G-buffer pass of adaptive and reprojected sampling) must outlive this
  // object; it may be null for uniform and foveated sampling.
  FrameViews(CameraRig rig, int width, int height, SamplingSetup sampling,
             const RenderScene* host = nullptr);

  // Frame `frame` seen through `camera` (the rig's centre).
  FrameInput make(int frame, const Camera& camera) const;

  const CameraRig& rig() const { return rig_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const SamplingSetup& sampling() const { return sampling_; }

 private:
  // Reprojected sampling: the centre's G-buffer, every other view's map and sample map.
  void reproject(FrameInput& in) const;

  CameraRig rig_;
  int width_, height_;
  SamplingSetup sampling_;
  const RenderScene* host_;
};

}  // namespace multiray
