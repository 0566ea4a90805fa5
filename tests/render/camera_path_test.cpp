#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "scene/camera_path.h"

namespace multiray {
namespace camera_path_test {

TEST(CameraPath, OrbitKeepsDistanceAndReturnsAfterOnePeriod) {
  const Camera base{{0, 1, 4}, {0, 1, 0}, {0, 1, 0}, 40};
  const CameraPath p = CameraPath::orbit(base, 10);
  for (int f = 0; f < 10; ++f) EXPECT_NEAR(length(p.at(f).eye - base.target), 4.0f, 1e-4f);
  EXPECT_NEAR(length(p.at(10).eye - base.eye), 0.0f, 1e-4f);
  EXPECT_GT(length(p.at(3).eye - base.eye), 1.0f);
  // A pure function of the frame: asking twice, in any order, gives the same camera.
  EXPECT_EQ(p.at(7).eye.x, p.at(7).eye.x);
}

TEST(CameraPath, KeyframesInterpolateThroughKeys) {
  std::vector<Keyframe> keys{{0, {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40}},
                             {10, {{10, 0, 0}, {10, 0, -1}, {0, 1, 0}, 60}},
                             {20, {{20, 0, 0}, {20, 0, -1}, {0, 1, 0}, 60}}};
  const CameraPath p = CameraPath::keyframes(keys);
  EXPECT_NEAR(p.at(10).eye.x, 10.0f, 1e-5f);
  EXPECT_NEAR(p.at(5).eye.x, 5.0f, 1e-4f);  // constant speed stays linear
  EXPECT_NEAR(p.at(15).eye.x, 15.0f, 1e-4f);
  EXPECT_NEAR(p.at(5).fov_y_deg, 50.0f, 1e-4f);
  EXPECT_NEAR(p.at(-5).eye.x, 0.0f, 1e-6f);  // clamped at the ends
  EXPECT_NEAR(p.at(99).eye.x, 20.0f, 1e-6f);
}

TEST(CameraPath, JsonFileAndItsErrors) {
  const std::string good = ::testing::TempDir() + "/path_good.json";
  std::ofstream(good) << R"({"keyframes":[{"frame":0,"eye":[0,0,5],"target":[0,0,0]},
                                          {"frame":4,"eye":[5,0,0],"target":[0,0,0],"fov":30}]})";
  const CameraPath p = CameraPath::from_json_file(good);
  EXPECT_NEAR(p.at(4).eye.x, 5.0f, 1e-6f);
  EXPECT_NEAR(p.at(4).fov_y_deg, 30.0f, 1e-6f);

  const std::string bad = ::testing::TempDir() + "/path_bad.json";
  for (const char* text :
       {"{", R"({"keyframes":[]})", R"({"keyframes":[{"frame":0,"eye":[0,0]}]})",
        R"({"keyframes":[{"frame":1,"eye":[0,0,1],"target":[0,0,0]},
                                            {"frame":1,"eye":[0,0,2],"target":[0,0,0]}]})"}) {
    std::ofstream(bad) << text;
    EXPECT_THROW(CameraPath::from_json_file(bad), InputError) << text;
  }
  EXPECT_THROW(CameraPath::from_json_file("/nonexistent/path.json"), InputError);
}

}  // namespace camera_path_test
}  // namespace multiray
