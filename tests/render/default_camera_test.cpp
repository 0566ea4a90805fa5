// The default camera (Scene::default_camera): a three-quarter view from outside the scene
// that keeps every corner of its bounding box in the image, for any up axis and aspect,
// through the rays PinholeCamera really generates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "render/default_view.h"
#include "render/path_tracer.h"
#include "scene/builders.h"
#include "scene/camera_path.h"

namespace multiray {
namespace default_camera_test {

// A box-shaped scene spanning lo..hi (one material, twelve triangles).
Scene box_scene(Vec3 lo, Vec3 hi) {
  Scene s;
  s.name = "box";
  const uint32_t m = add_material(s, Material{.name = "grey"});
  add_box(s, (lo + hi) * 0.5f, (hi - lo) * 0.5f, 0.0f, m);
  return s;
}

struct Projection {
  float x, y;   // pixels, y down, as PinholeCamera::ray takes them
  float depth;  // along the view direction
};

// Where point `p` lands in a w x h image: the inverse of PinholeCamera::ray.
Projection project(const PinholeCamera& cam, Vec3 p, int w, int h) {
  const Vec3 q = p - cam.eye;
  const float z = dot(q, cam.forward);
  const float sx = dot(q, cam.right) / z / cam.scale_x, sy = dot(q, cam.up) / z / cam.scale_y;
  return {(sx + 1.0f) * 0.5f * float(w), (1.0f - sy) * 0.5f * float(h), z};
}

// Every corner of the scene's bounds projects in front of the camera and inside the image;
// the widest one reaches at least `fill` of the half image (the box is not lost in a
// corner of the frame). Returns the largest normalised offset from the centre.
float check_framing(const Scene& s, const Camera& c, int w, int h, const std::string& what,
                    float fill = 0.8f) {
  const PinholeCamera cam(c, w, h);
  const Bounds3 b = s.bounds();
  float widest = 0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    const Projection pr = project(cam, p, w, h);
    EXPECT_GT(pr.depth, 0.0f) << what << " corner " << i;
    EXPECT_GE(pr.x, 0.0f) << what << " corner " << i;
    EXPECT_LE(pr.x, float(w)) << what << " corner " << i;
    EXPECT_GE(pr.y, 0.0f) << what << " corner " << i;
    EXPECT_LE(pr.y, float(h)) << what << " corner " << i;
    widest = std::max({widest, std::abs(2.0f * pr.x / float(w) - 1.0f),
                       std::abs(2.0f * pr.y / float(h) - 1.0f)});
  }
  EXPECT_GE(widest, fill) << what << ": the scene fills too little of the image";
  return widest;
}

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

bool inside(const Bounds3& b, Vec3 p) {
  return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z &&
         p.z <= b.hi.z;
}

// A Y-up scene (glTF's convention): a wide, low, off-centre box seen from the front-right
// (+z, +x) and above (+y), whole, for wide, square and tall images.
TEST(DefaultCamera, FramesAYUpSceneFromAThreeQuarterView) {
  const Scene s = box_scene({-30, 2, -5}, {10, 8, 3});
  for (auto [w, h] : {std::pair{320, 180}, {200, 200}, {90, 270}}) {
    const std::string what = "y-up " + std::to_string(w) + "x" + std::to_string(h);
    const Camera c = s.default_camera(float(w) / float(h));
    check_framing(s, c, w, h, what);
    const Vec3 to_eye = c.eye - s.bounds().center();
    EXPECT_GT(to_eye.z, 0.0f) << what << ": in front (+z)";
    EXPECT_GT(to_eye.x, 0.0f) << what << ": to the right (+x)";
    EXPECT_GT(to_eye.y, 0.0f) << what << ": above (+y)";
    EXPECT_FALSE(inside(s.bounds(), c.eye)) << what;
    EXPECT_TRUE(same(c.up, Vec3(0, 1, 0))) << what;
  }
}

// A Z-up scene (--up z: CAD, Blender, CT volumes): seen from the front (-y), right (+x) and
// above (+z), not from above along -z.
TEST(DefaultCamera, FramesAZUpSceneFromAThreeQuarterView) {
  const Scene s = box_scene({0, 0, 0}, {4, 2, 9});  // tall along z
  for (auto [w, h] : {std::pair{320, 180}, {100, 300}}) {
    const std::string what = "z-up " + std::to_string(w) + "x" + std::to_string(h);
    const Camera c = s.default_camera(float(w) / float(h), Vec3(0, 0, 1));
    check_framing(s, c, w, h, what);
    const Vec3 to_eye = c.eye - s.bounds().center();
    EXPECT_LT(to_eye.y, 0.0f) << what << ": in front (-y)";
    EXPECT_GT(to_eye.x, 0.0f) << what << ": to the right (+x)";
    EXPECT_GT(to_eye.z, 0.0f) << what << ": above (+z)";
    // Above, but far from looking straight down: the elevation is kDefaultElevationDeg.
    const float elevation = std::asin(to_eye.z / length(to_eye)) * 180.0f / kPi;
    EXPECT_NEAR(elevation, kDefaultElevationDeg, 0.01f) << what;
    EXPECT_FALSE(inside(s.bounds(), c.eye)) << what;
    // Upright: the image's up is the scene's +z side.
    const PinholeCamera cam(c, w, h);
    EXPECT_GT(cam.up.z, 0.9f) << what;
  }
}

// Every signed axis gives a framed, upright, outside view; a flat scene (zero extent on
// one axis) too, and scenes far from the origin or tiny.
TEST(DefaultCamera, EveryUpAxisAndDegenerateExtents) {
  const Scene scenes[] = {box_scene({-1, -1, -1}, {1, 1, 1}), box_scene({-5, 0, -5}, {5, 0, 5}),
                          box_scene({1e5f, 2e5f, 3e5f}, {1e5f + 2, 2e5f + 1, 3e5f + 3}),
                          box_scene({0, 0, 0}, {1e-3f, 2e-3f, 1e-3f})};
  for (const Scene& s : scenes)
    for (const char* name : {"x", "+x", "-x", "y", "-y", "z", "+z", "-z"}) {
      Vec3 up;
      ASSERT_TRUE(up_axis_vector(name, up)) << name;
      const Camera c = s.default_camera(16.0f / 9.0f, up);
      const std::string what = std::string("up ") + name;
      check_framing(s, c, 160, 90, what, 0.6f);
      EXPECT_GT(dot(c.eye - s.bounds().center(), up), 0.0f) << what << ": above";
      EXPECT_GT(dot(PinholeCamera(c, 160, 90).up, up), 0.9f) << what << ": upright";
    }
}

TEST(DefaultCamera, UpAxisNames) {
  Vec3 up;
  ASSERT_TRUE(up_axis_vector("-z", up));
  EXPECT_TRUE(same(up, Vec3(0, 0, -1)));
  ASSERT_TRUE(up_axis_vector("y", up));
  EXPECT_TRUE(same(up, Vec3(0, 1, 0)));
  for (const char* bad : {"", "+", "w", "Y", "zz", "+-x", "1", "y "})
    EXPECT_FALSE(up_axis_vector(bad, up)) << "'" << bad << "'";
}

// FBX's GlobalSettings name the up axis by index and sign (assimp's "UpAxis" and
// "UpAxisSign" metadata); anything else says nothing.
TEST(DefaultCamera, FbxUpAxisMetadata) {
  Vec3 up;
  ASSERT_TRUE(fbx_up_axis(2, 1, up));
  EXPECT_TRUE(same(up, Vec3(0, 0, 1)));
  ASSERT_TRUE(fbx_up_axis(1, 1, up));
  EXPECT_TRUE(same(up, Vec3(0, 1, 0)));
  ASSERT_TRUE(fbx_up_axis(0, -1, up));
  EXPECT_TRUE(same(up, Vec3(-1, 0, 0)));
  for (auto [axis, sign] : {std::pair{3, 1}, {-1, 1}, {1, 0}, {2, 2}})
    EXPECT_FALSE(fbx_up_axis(axis, sign, up)) << axis << " " << sign;
}

// The built-in Cornell box keeps its own camera; the default is only for scenes without.
TEST(DefaultCamera, TheCornellBoxKeepsItsCamera) {
  const Scene s = make_cornell_box();
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_TRUE(same(s.cameras[0].eye, Vec3(0, 1, 3.9f)));
  EXPECT_TRUE(same(s.cameras[0].target, Vec3(0, 1, 0)));
}

// Objects get the three-quarter view; a box open on one side (the Cornell box without its
// camera, as McGuire's and Mitsuba's files are) is looked into through that side, since
// from outside at an angle most of what the camera sees is the back of a wall.
TEST(DefaultCamera, OpenBoxesAreSeenThroughTheirOpenSide) {
  const float aspect = 16.0f / 9.0f;
  {
    const Scene closed = box_scene({-1, 0, -2}, {3, 1, 1});
    const RenderScene rs(closed);
    const Camera c = choose_default_camera(rs, aspect, Vec3(0, 1, 0));
    const Camera q = closed.default_camera(aspect);
    EXPECT_TRUE(same(c.eye, q.eye)) << "a closed box gets the three-quarter view";
    EXPECT_GT(front_face_share(rs, c, aspect), 0.99f);
  }
  Scene open = make_cornell_box();  // open towards +z
  open.cameras.clear();
  {
    const RenderScene rs(open);
    const Camera c = choose_default_camera(rs, aspect, Vec3(0, 1, 0));
    const Vec3 to_eye = c.eye - open.bounds().center();
    EXPECT_NEAR(to_eye.x, 0.0f, 1e-4f);
    EXPECT_NEAR(to_eye.y, 0.0f, 1e-4f);
    EXPECT_GT(to_eye.z, 0.0f);
    EXPECT_LT(front_face_share(rs, open.default_camera(aspect), aspect), 0.8f)
        << "the three-quarter view sees mostly the outside of the right wall";
    check_framing(open, c, 160, 90, "open +z");
  }
  // The same box turned to open towards -z (as Mitsuba's, whose camera is at z = -800).
  for (Vec3& p : open.positions) p = Vec3(-p.x, p.y, -p.z);
  for (Vec3& n : open.normals) n = Vec3(-n.x, n.y, -n.z);
  {
    const RenderScene rs(open);
    const Camera c = choose_default_camera(rs, aspect, Vec3(0, 1, 0));
    EXPECT_LT(c.eye.z - open.bounds().center().z, 0.0f) << "seen from the back (-z)";
  }
}

// An orbit turns about the world axis nearest the camera's up: with up +z the eye stays
// at its height in z (with +y, in y, as always).
TEST(DefaultCamera, OrbitsTurnAboutTheUpAxis) {
  const Scene s = box_scene({0, 0, 0}, {4, 2, 9});
  for (Vec3 up : {Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(-1, 0, 0)}) {
    const Camera base = s.default_camera(1.5f, up);
    const CameraPath path = CameraPath::orbit(base, 8.0f);
    const float height = dot(base.eye, up);
    for (int f = 1; f < 8; ++f) {
      const Camera c = path.at(f);
      EXPECT_NEAR(dot(c.eye, up), height, 1e-4f * (1 + std::abs(height))) << "frame " << f;
      EXPECT_GT(length(c.eye - base.eye), 0.1f) << "frame " << f << ": the eye moves";
      EXPECT_NEAR(length(c.eye - base.target), length(base.eye - base.target), 1e-3f);
    }
  }
}

// A room 10 x 3 x 6 (long along x) built as a building is: floor, ceiling and four walls
// each a solid slab (every face facing out of its slab, so the room's air sees front
// faces and so does the outside view), with a column in the middle of the floor.
Scene room_scene() {
  Scene s;
  s.name = "room";
  const uint32_t m = add_material(s, Material{.name = "plaster"});
  const float t = 0.2f;                                                   // slab thickness
  add_box(s, Vec3(0, -t / 2, 0), Vec3(5 + t, t / 2, 3 + t), 0.0f, m);     // floor
  add_box(s, Vec3(0, 3 + t / 2, 0), Vec3(5 + t, t / 2, 3 + t), 0.0f, m);  // ceiling
  add_box(s, Vec3(-5 - t / 2, 1.5f, 0), Vec3(t / 2, 1.5f, 3), 0.0f, m);   // walls
  add_box(s, Vec3(5 + t / 2, 1.5f, 0), Vec3(t / 2, 1.5f, 3), 0.0f, m);
  add_box(s, Vec3(0, 1.5f, -3 - t / 2), Vec3(5, 1.5f, t / 2), 0.0f, m);
  add_box(s, Vec3(0, 1.5f, 3 + t / 2), Vec3(5, 1.5f, t / 2), 0.0f, m);
  add_box(s, Vec3(0, 1.5f, 0), Vec3(0.4f, 1.5f, 0.4f), 0.0f, m);  // column
  return s;
}

// `s` with every triangle's winding reversed: faces that faced out now face in.
Scene flipped(Scene s) {
  for (size_t i = 0; i + 2 < s.indices.size(); i += 3)
    std::swap(s.indices[i + 1], s.indices[i + 2]);
  for (Vec3& n : s.normals) n = -n;
  return s;
}

// A camera inside the room: in its air (not in a slab or the column, eye height a
// quarter of the way up), looking along the long axis (x), wider than the outside view,
// and recorded as "default-interior".
TEST(DefaultCamera, AnInteriorIsSeenFromInside) {
  const Scene room = room_scene();
  const RenderScene rs(room);
  const InteriorProbe probe = probe_interior(rs, Vec3(0, 1, 0));
  EXPECT_TRUE(is_interior(probe)) << probe.hit_share << " " << probe.front_share;
  const DefaultView v = choose_default_view(rs, 16.0f / 9.0f, Vec3(0, 1, 0));
  EXPECT_EQ(v.source, "default-interior");
  const Camera& c = v.camera;
  EXPECT_GT(c.eye.y, 0.5f);
  EXPECT_LT(c.eye.y, 1.0f) << "a quarter of the way up";
  EXPECT_LT(std::abs(c.eye.x), 5.0f);
  EXPECT_LT(std::abs(c.eye.z), 3.0f);
  EXPECT_FALSE(std::abs(c.eye.x) < 0.4f && std::abs(c.eye.z) < 0.4f) << "inside the column";
  const Vec3 dir = normalize(c.target - c.eye);
  EXPECT_GT(std::abs(dir.x), 0.99f) << "along the long axis";
  EXPECT_GT(dot(dir, Vec3(-c.eye.x, 0, 0)), 0.0f) << "towards the far end";
  EXPECT_EQ(c.fov_y_deg, kInteriorFovDeg);
  EXPECT_GT(front_face_share(rs, c, 16.0f / 9.0f), 0.95f);
  // The same room turned Z-up (--up z) is found the same way.
  Scene z_up = room;
  for (Vec3& p : z_up.positions) p = Vec3(p.x, -p.z, p.y);
  const DefaultView vz = choose_default_view(RenderScene(z_up), 1.5f, Vec3(0, 0, 1));
  EXPECT_EQ(vz.source, "default-interior");
  EXPECT_GT(vz.camera.eye.z, 0.5f);
  EXPECT_LT(vz.camera.eye.z, 1.0f);
}

// A room modelled as one shell whose faces face in (its outside view sees only backs) is
// an interior too: its walls are the bounds' sides.
TEST(DefaultCamera, AnInwardFacingShellRoomIsAnInterior) {
  const Scene shell = flipped(box_scene({-5, 0, -3}, {5, 3, 3}));
  const DefaultView v = choose_default_view(RenderScene(shell), 16.0f / 9.0f, Vec3(0, 1, 0));
  EXPECT_EQ(v.source, "default-interior");
}

// Objects keep the outside view: a closed box, a blob wound inwards like the Stanford
// bunny (its centre is inside and its rays see front faces, but its outside sees backs
// and its surface is not the bounds' sides), and the Cornell box open on one side.
TEST(DefaultCamera, ObjectsAndOpenBoxesStayOutside) {
  const float aspect = 16.0f / 9.0f;
  Scene blob;
  blob.name = "blob";
  const uint32_t m = add_material(blob, Material{.name = "grey"});
  // Two boxes, one turned 45 degrees: a union whose surface mostly lies inside its bounds.
  add_box(blob, Vec3(0, 0, 0), Vec3(1, 1, 1), 0.0f, m);
  add_box(blob, Vec3(0, 0, 0), Vec3(1.3f, 0.7f, 1.3f), 45.0f, m);
  Scene cornell = make_cornell_box();
  cornell.cameras.clear();
  const std::pair<std::string, Scene> objects[] = {
      {"closed box", box_scene({-1, 0, -2}, {3, 1, 1})},
      {"inward blob", flipped(blob)},
      {"cornell box", cornell}};
  for (const auto& [what, s] : objects) {
    const RenderScene rs(s);
    const DefaultView v = choose_default_view(rs, aspect, Vec3(0, 1, 0));
    EXPECT_EQ(v.source, "default") << what;
    EXPECT_FALSE(inside(s.bounds(), v.camera.eye)) << what;
  }
}

// A volume's default view looks at the side `front` names (a CT's anterior), from the
// three-quarter direction round it, for either sign and axis.
TEST(DefaultCamera, VolumesAreSeenFromTheirFront) {
  const Scene s = box_scene({-2, -2, -1}, {2, 2, 1});
  for (Vec3 front : {Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(1, 0, 0), Vec3(-1, 0, 0)}) {
    const Camera c = default_volume_camera(s, 1.5f, Vec3(0, 0, 1), front);
    const Vec3 to_eye = normalize(c.eye - c.target);
    const float horizontal = std::sqrt(to_eye.x * to_eye.x + to_eye.y * to_eye.y);
    EXPECT_NEAR(dot(to_eye, front) / horizontal, std::cos(kDefaultAzimuthDeg * kPi / 180.0f),
                1e-4f)
        << front.x << "," << front.y;
    EXPECT_GT(to_eye.z, 0.0f);
    check_framing(s, c, 150, 100, "volume");
  }
  // Without a horizontal front, view_direction's convention (-y for +z up).
  const Camera c = default_volume_camera(s, 1.5f, Vec3(0, 0, 1), Vec3(0, 0, 1));
  EXPECT_LT(c.eye.y, 0.0f);
}

// A file's own camera that crops the scene is told (issue 51 item 8: the 2CylinderEngine's
// camera cut it at the right and bottom with no word).
TEST(DefaultCamera, ShareOfTheSceneOutsideACamerasFrame) {
  const Scene s = box_scene({-1, -1, -1}, {1, 1, 1});
  const Camera framing = s.default_camera(16.0f / 9);
  EXPECT_EQ(share_outside_frame(s, framing, 16.0f / 9), 0.0f);
  // Aimed past the box's right edge: the corners on the left are out of a narrow view.
  Camera off = framing;
  off.fov_y_deg = 10;
  off.target = framing.target + Vec3(3, 0, 0);
  EXPECT_GT(share_outside_frame(s, off, 1.0f), kCroppedShare);
  // Looking away: everything is behind it.
  Camera away = framing;
  away.target = framing.eye + (framing.eye - framing.target);
  EXPECT_EQ(share_outside_frame(s, away, 1.0f), 1.0f);
  // From inside the bounds (an interior view): not a crop.
  Camera inside = framing;
  inside.eye = Vec3(0, 0, 0), inside.target = Vec3(0, 0, -1);
  EXPECT_EQ(share_outside_frame(s, inside, 1.0f), 0.0f);
}

}  // namespace default_camera_test
}  // namespace multiray
