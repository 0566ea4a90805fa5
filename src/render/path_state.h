// A path of the CPU's wavefront (path_tracer.cpp, shadow_catcher.cpp): the integrator's
// state (render/shared/path.h) and what the shadow catcher adds. Paths advance in
// batches: all rays of a batch are traced, then all hits shaded, then all shadow rays
// traced. The arithmetic per path is exactly the depth-first loop's, so images are
// unchanged, but the cache misses of different paths' shading overlap instead of queueing
// one after another.
#pragma once

#include "render/shadow_catcher.h"
#include "render/shared/path.h"

namespace multiray {

struct WavefrontPath : PathState {
  explicit WavefrontPath(SampleStream s) { path_init(this, s); }
  // With a shadow catcher only: what the camera ray met first, and for the catcher, its
  // radiance as if the virtual objects were not there (render/shadow_catcher.h).
  SampleKind kind = SampleKind::background;
  Vec3 L_without{0.0f};
  // Feature buffers (render/shared/aov.h): set by aov_init only when the settings ask for
  // them, untouched (and never read) otherwise.
  AovSample aov;
};

}  // namespace multiray
