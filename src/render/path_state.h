// The state of one camera path between bounces, shared by the path tracer's files
// (path_tracer.cpp, shadow_catcher.cpp). Paths advance in batches (a wavefront): all rays
// of a batch are traced, then all hits shaded, then all shadow rays traced. The arithmetic
// per path is exactly the depth-first loop's, so images are unchanged, but the cache
// misses of different paths' shading overlap instead of queueing one after another.
#pragma once

#include "render/accel.h"
#include "render/shadow_catcher.h"
#include "render/shared/sobol.h"

namespace multiray {

struct PathState {
  explicit PathState(SampleStream s) : u(s) {}
  Ray ray;
  Vec3 L{0.0f}, beta{1.0f};
  SampleStream u;  // the path's sample values (render/shared/sobol.h)
  float prev_pdf = 0;
  Vec3 prev_normal{0.0f};     // geometric normal at the last vertex (environment sampling)
  bool prev_specular = true;  // the camera ray counts as specular: emission seen directly
  bool alive = true;
  int depth = 0;
  bool has_shadow = false;  // a next-event ray is waiting to be traced
  Ray shadow;
  Vec3 shadow_contribution;
  // With a shadow catcher only: what the camera ray met first, and for the catcher, its
  // radiance as if the virtual objects were not there (render/shadow_catcher.h).
  SampleKind kind = SampleKind::background;
  Vec3 L_without{0.0f};
};

}  // namespace multiray
