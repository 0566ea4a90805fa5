// The default camera of a mesh scene without one of its own (and without --camera).
//
// Scene::default_camera's three-quarter view from outside suits objects (a bunny, a
// helmet, an engine). It does not suit scenes made to be seen from one open side, such as
// a Cornell box: from outside and at an angle, most of what it sees is the back of a wall.
// So a few views are tried, each framing the bounding box, and the first in order of
// preference whose share of front faces (by winding: the side emission and the loaders'
// normals face) is close to the best share is taken.
//
// Nor does it suit interiors (Sponza's atrium, a room): from outside they are a closed
// box. An interior is told by rays cast roughly horizontally from points inside the
// bounds: in a room nearly all of them hit, and hit the front faces of walls facing in.
// Inside a closed object (a bunny) they hit back faces; from a box open on one side (a
// Cornell box) a quarter of them escape. An interior gets a camera inside, at a free spot
// (interior_camera), looking along its longest horizontal axis.
#pragma once

#include <optional>
#include <string>
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

// The default outside camera for the mesh `rs.scene` with up axis `up` (see the file
// comment).
Camera choose_default_camera(const RenderScene& rs, float aspect, Vec3 up);

// What rays cast from points inside the bounds (but not inside a solid), within
// kProbeElevationDeg of the horizon, see: the share of them that hit anything, the share
// of those hits on front faces, and the share of those on the bounds' vertical sides
// (within kSideTolerance of the horizontal extent); with the share of front faces the
// outside three-quarter view sees.
struct InteriorProbe {
  float hit_share = 0, front_share = 0, side_share = 0, outside_front_share = 0;
};
constexpr float kProbeElevationDeg = 10.0f, kSideTolerance = 0.02f;
InteriorProbe probe_interior(const RenderScene& rs, Vec3 up);
// An interior: rays nearly all hit (kInteriorHitShare; a box open on one side lets about
// a seventh escape) and mostly the front faces of walls (kInteriorFrontShare). Winding
// alone cannot tell a room from a closed object wound inwards (the Stanford bunny's
// faces all face in), so besides, the walls must either have an outside that faces out
// too (a building's thick walls: the outside view sees front faces) or be the bounds'
// sides themselves (a room modelled as one inward-facing shell).
constexpr float kInteriorHitShare = 0.95f, kInteriorFrontShare = 0.7f;
bool is_interior(const InteriorProbe& probe);

// The vertical field of view inside, degrees: a room is seen from within it, so wider
// than kDefaultFovDeg.
constexpr float kInteriorFovDeg = 60.0f;
// A camera inside the scene's bounds at a free spot: not inside a solid (every probe ray
// from it hits a front face or nothing, none nearer than a clearance), above a floor, at a
// quarter of the height from that floor to the ceiling (or the bounds' top), looking
// horizontally along whichever direction of the longer horizontal axis is open the
// furthest. Its target is where an orbit turns: close enough that the orbit's circle
// fits the room's shorter side. Empty when no candidate spot is free.
std::optional<Camera> interior_camera(const RenderScene& rs, Vec3 up);

// The default camera and where it came from: "default" (outside, choose_default_camera)
// or "default-interior" (interior_camera, when is_interior(probe_interior())).
struct DefaultView {
  Camera camera;
  std::string source;
};
DefaultView choose_default_view(const RenderScene& rs, float aspect, Vec3 up);

// The default camera of a volume: Scene::default_camera's three-quarter view round `up`,
// with azimuth 0 at the side `front` (a signed world axis) faces: for a CT the patient's
// anterior (VolumeOrientation in volume/volume.h). A `front` along `up` is ignored
// (view_direction's front is used).
Camera default_volume_camera(const Scene& scene, float aspect, Vec3 up, Vec3 front);

// The share of the scene's vertices that `camera` does not show in an image of width /
// height `aspect` (behind it or outside the frame), over at most `max_points` of them taken
// evenly; 0 without vertices or when the eye is inside the scene's bounds (a view from
// inside sees a part by design). A file's own camera that leaves part of an object outside
// crops it (glTF's 2CylinderEngine: yfov 18° at aspect 1, cut at the right and bottom),
// which the run then says (kCroppedShare).
float share_outside_frame(const Scene& scene, const Camera& camera, float aspect,
                          size_t max_points = 65536);
// The share of vertices outside the frame past which a file's camera is said to crop
// (0.1%: 2CylinderEngine's camera leaves 0.4% out at 16:9, its bottom cut off).
constexpr float kCroppedShare = 0.001f;

}  // namespace multiray
