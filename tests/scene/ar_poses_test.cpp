// AR capture poses (scene/ar_poses.h): ARKit-style transforms and intrinsics become the
// cameras they describe, a path through them, and bad documents are refused naming the pose.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/ar_poses.h"

namespace multiray {
namespace ar_poses_test {

nlohmann::json one_pose(std::vector<float> transform, std::vector<float> k = {100, 100, 80, 60}) {
  return {{"image", {160, 120}}, {"intrinsics", k}, {"poses", {{{"transform", transform}}}}};
}

// A camera 5 units along +z from the origin, looking back at it (-Z forward), y up.
const std::vector<float> kIdentityAt5 = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 5, 1};

TEST(ArPoses, TransformAndIntrinsicsGiveTheCamera) {
  const ArPoses p = ar_poses_from_json(one_pose(kIdentityAt5), "t");
  ASSERT_EQ(p.cameras.size(), 1u);
  const Camera& c = p.cameras[0];
  EXPECT_FLOAT_EQ(c.eye.z, 5.0f);
  EXPECT_FLOAT_EQ(c.eye.y, 1.0f);
  EXPECT_FLOAT_EQ(c.target.z, 4.0f);  // one unit along -Z
  EXPECT_FLOAT_EQ(c.up.y, 1.0f);
  // fov_y = 2 atan(60 / 100)
  EXPECT_NEAR(c.fov_y_deg, 2.0 * std::atan(0.6) * 180.0 / M_PI, 1e-4);
  EXPECT_EQ(p.width, 160);
}

TEST(ArPoses, CamerasRoundTripThroughTheDocument) {
  const Camera a{{1, 2, 3}, {0, 0.5f, 0}, {0, 1, 0}, 50.0f};
  const Camera b{{-2, 1, 4}, {0.2f, 0, -1}, {0, 1, 0}, 50.0f};
  const ArPoses p = ar_poses_from_json(ar_poses_to_json({a, b}, 320, 240), "t");
  ASSERT_EQ(p.cameras.size(), 2u);
  const Camera& c = p.cameras[1];
  EXPECT_NEAR(c.eye.x, -2.0f, 1e-5);
  const Vec3 want = normalize(b.target - b.eye), got = c.target - c.eye;
  EXPECT_NEAR(dot(want, got), 1.0f, 1e-5);
  EXPECT_NEAR(c.fov_y_deg, 50.0f, 1e-3);
  // The path's frame i is pose i.
  const CameraPath path = p.path();
  EXPECT_NEAR(path.at(1).eye.x, -2.0f, 1e-5);
  EXPECT_NEAR(path.at(0).eye.z, 3.0f, 1e-5);
}

// A long lens (0.2 degrees, twice the narrowest allowed) is still a camera.
TEST(ArPoses, ANarrowButRealFieldOfViewIsKept) {
  const float f = 60.0f / std::tan(0.1f * float(M_PI) / 180.0f);
  const ArPoses p = ar_poses_from_json(one_pose(kIdentityAt5, {f, f, 80, 60}), "t");
  EXPECT_NEAR(p.cameras[0].fov_y_deg, 0.2f, 1e-4);
}

TEST(ArPoses, BadDocumentsAreRefusedNamingThePose) {
  const auto refused = [](const nlohmann::json& doc, const std::string& word) {
    try {
      ar_poses_from_json(doc, "p.json");
      ADD_FAILURE() << "accepted: " << doc.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  refused(nlohmann::json::object(), "poses");
  refused(one_pose({1, 0, 0}), "16 numbers");
  std::vector<float> scaled = kIdentityAt5;
  scaled[0] = 2;
  refused(one_pose(scaled), "pose 0: the transform's rotation");
  std::vector<float> mirrored = kIdentityAt5;
  mirrored[10] = -1;
  refused(one_pose(mirrored), "right-handed");
  std::vector<float> projective = kIdentityAt5;
  projective[3] = 0.5f;
  refused(one_pose(projective), "last row");
  refused(one_pose(kIdentityAt5, {100, 150, 80, 60}), "fx and fy");
  refused(one_pose(kIdentityAt5, {100, 100, 20, 60}), "principal point");
  refused(one_pose(kIdentityAt5, {0, 0, 80, 60}), "focal");
  // A field of view of 1e-28 degrees (issue 53) or just under kMinPoseFovDeg: refused.
  nlohmann::json tele = one_pose(kIdentityAt5);
  tele["intrinsics"] = {1e30, 1e30, 80, 60};  // doubles: the largest magnitude taken
  refused(tele, "pose 0: a focal length of 1e+30 pixels is a field of view of ");
  refused(one_pose(kIdentityAt5, {1e5f, 1e5f, 80, 60}), "field of view of 0.0687");
  nlohmann::json nan_doc = one_pose(kIdentityAt5);
  nan_doc["poses"][0]["transform"][12] = "x";
  refused(nan_doc, "finite number");
  nlohmann::json no_image = one_pose(kIdentityAt5);
  no_image.erase("image");
  refused(no_image, "image");
}

}  // namespace ar_poses_test
}  // namespace multiray
