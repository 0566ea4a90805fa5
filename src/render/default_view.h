// The default camera of a mesh scene without one of its own (and without --camera).
//
// Scene::default_camera's three-quarter view from outside suits objects (a bunny, a
// helmet, an engine). It does not suit scenes made to be seen from one open side, such as
// a Cornell box: from outside and at an angle, most of what it sees is the back of a wall.
// So a few views are tried, each framing the bounding box, and the first in order of
// preference whose share of front faces (by winding: the side emission and the loaders'
// normals face) is close to the best share is taken.
#pragma once

#include <vector>

#include "render/render_types.h"

namespace multiray {

// One candidate view: azimuth and elevation for Scene::default_camera, in order of
// preference (the three-quarter view first, then straight views into open sides).
struct DefaultViewCandidate {
  float azimuth_deg, elevation_deg;
};
const std::vector<DefaultViewCandidate>& default_view_candidates();

// The share of hits that see a front face among a grid of `nx` x `ny` rays through the
// image of `camera` (aspect `aspect`); 0 when nothing is hit.
float front_face_share(const RenderScene& rs, const Camera& camera, float aspect, int nx = 32,
                       int ny = 18);

// A candidate is taken when its share is within this of the best one's.
constexpr float kFrontShareSlack = 0.1f;

// The default camera for the mesh `rs.scene` with up axis `up` (see the file comment).
Camera choose_default_camera(const RenderScene& rs, float aspect, Vec3 up);

}  // namespace multiray
