// Progressive refinement for the live viewer (issue 33, "interactive at any frame rate"):
// the session renders every frame with few samples (`frame_spp`), so moving the camera
// stays fluid, and while nothing changes the viewer shows the mean of the frames rendered
// so far, which converges to a `target_spp` image and then stands. The session renders
// such frames progressively (Session::set_progressive): each continues the sample
// sequence of the first frame under the camera, so the mean of N frames of S samples is,
// bit for bit, the image one render of N x S samples would give, with the even spread of
// its samples (render/shared/sobol.h), not N independent images averaged.
// Pure: images in, image out; no server, no session (the viewer, app/viewer/live_view.h,
// feeds it the session's frames; tests/engine checks it against one render of all the
// samples).
#pragma once

#include "core/image.h"
#include "engine/refine_features.h"
#include "scene/scene.h"

namespace multiray {

// What decides a frame's image apart from its samples. Frames are averaged only while it
// stays the same. The balancer is not in it: the split never changes the pixels.
struct RefineKey {
  Camera camera;
  int view = 0;
  int generation = 0;  // bumped by anything else that changes the image (a style)
  // The scale the frame was rendered at (FrameRecord::quality.image_scale): a frame
  // rendered smaller and enlarged (the viewer's, while the camera moves and for a moment
  // after) is never averaged with full-size ones, which start again from their first.
  double image_scale = 1.0;
  bool operator==(const RefineKey& o) const;
};

class Refinement {
 public:
  // `frame_spp` samples per pixel in each frame, `target_spp` the image to converge to;
  // both at least 1 (smaller values are taken as 1). With frame_spp >= target_spp the
  // first frame under a key is already converged and stands.
  Refinement(int frame_spp, int target_spp);

  // The image to show after a frame rendered under `key`: the mean of this frame and the
  // earlier ones under the same key, as long as their samples stay within target_spp;
  // once it is reached, the converged image (later frames under that key add nothing).
  // A different key starts again from this frame. Frames with feature buffers give the
  // image theirs too (engine/refine_features.h); a change to or from them starts again.
  const Framebuffer& add(const Framebuffer& image, const RefineKey& key);

  // Samples per pixel of the image add() returned last.
  int samples() const { return frames_ * frame_spp_; }
  // Whether the last add() started again from its frame (a new key, size or layers).
  bool restarted() const { return restarted_; }
  int target_spp() const { return target_spp_; }

 private:
  int frame_spp_, target_spp_;
  RefineKey key_;
  int frames_ = 0;
  bool restarted_ = false;
  std::vector<Vec3> sum_;         // the frames' radiance summed, per pixel
  std::vector<float> alpha_sum_;  // and their alpha, when they have it
  FeatureRefinement features_;    // and their feature buffers, when they have them
  Framebuffer mean_;
};

}  // namespace multiray
