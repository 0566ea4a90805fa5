// Camera paths only ever yield cameras camera_problem() accepts: keyframe files with an
// unusable camera or a number that is not a finite float are refused with one line
// naming the file and the keyframe, interpolation between valid keys never produces an
// unusable camera, and orbit periods that would give NaN are refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/camera_check.h"
#include "scene/camera_path.h"

namespace multiray {
namespace camera_input_test {

namespace fs = std::filesystem;

std::string write_path(const std::string& name, const std::string& json) {
  const std::string p = (fs::temp_directory_path() /
                         ("multiray_cam_" + std::to_string(getpid()) + "_" + name + ".json"))
                            .string();
  std::ofstream(p) << json;
  return p;
}

// Loads a two-keyframe file whose keyframe 1 has the members `key1` and expects one
// InputError line naming the file, keyframe 1 and `word`.
void expect_refused(const std::string& name, const std::string& key1, const std::string& word) {
  const std::string path = write_path(
      name, R"({"keyframes":[{"frame":0,"eye":[0,0,5],"target":[0,0,0]},{)" + key1 + "}]}");
  try {
    CameraPath::from_json_file(path);
    ADD_FAILURE() << "accepted " << key1;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("keyframe 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find(word), std::string::npos) << "'" << word << "' not in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError for " << key1 << ": " << e.what();
  }
  fs::remove(path);
}

TEST(CameraInput, KeyframeFilesRefuseUnusableCameras) {
  expect_refused("same", R"("frame":9,"eye":[1,2,3],"target":[1,2,3])", "same point");
  expect_refused("zero_up", R"("frame":9,"eye":[0,0,5],"target":[0,0,0],"up":[0,0,0])",
                 "zero length");
  expect_refused("parallel_up", R"("frame":9,"eye":[0,0,5],"target":[0,0,0],"up":[0,0,1])",
                 "parallel");
  expect_refused("huge", R"("frame":9,"eye":[3e38,0,0],"target":[0,0,0])", "1e18");
}

TEST(CameraInput, KeyframeFilesRefuseNumbersThatAreNotFiniteFloats) {
  expect_refused("eye_inf", R"("frame":9,"eye":[1e39,0,0],"target":[0,0,0])",
                 "'eye' is not a finite");
  expect_refused("frame_inf", R"("frame":1e39,"eye":[0,0,1],"target":[0,0,0])",
                 "'frame' is not a finite");
  expect_refused("fov_inf", R"("frame":9,"eye":[0,0,1],"target":[0,0,0],"fov":1e39)",
                 "'fov' is not a finite");
  expect_refused("fov_text", R"("frame":9,"eye":[0,0,1],"target":[0,0,0],"fov":"wide")",
                 "'fov' must be a number");
}

TEST(CameraInput, ProgrammaticKeyframesAreCheckedToo) {
  const Camera good{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45};
  const Camera bad{{0, 0, 5}, {0, 0, 5}, {0, 1, 0}, 45};
  EXPECT_THROW(CameraPath::keyframes({{0, good}, {1, bad}}), InputError);
  EXPECT_THROW(CameraPath::keyframes({{0, good}, {INFINITY, good}}), InputError);
}

// Between two valid keys the interpolated camera can be unusable: here eye and target
// swap places, so halfway they meet; and the up vectors are opposite, so halfway their
// interpolation is zero. at() must still give a usable camera for every frame.
TEST(CameraInput, InterpolatedCamerasStayUsable) {
  const CameraPath swap = CameraPath::keyframes(
      {{0, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 45}}, {2, {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45}}});
  const CameraPath flip = CameraPath::keyframes(
      {{0, {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45}}, {2, {{0, 0, 5}, {0, 0, 0}, {0, -1, 0}, 45}}});
  // Catmull-Rom overshoot: keys 1 and 2 both have the eye at z = 1, but the far key 3
  // (z = 34) swings the spline between them to (18 - 0 - 34) / 16 = -1 at frame 2, the
  // target.
  const CameraPath overshoot =
      CameraPath::keyframes({{0, {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 45}},
                             {1, {{0, 0, 1}, {0, 0, -1}, {0, 1, 0}, 45}},
                             {3, {{0, 0, 1}, {0, 0, -1}, {0, 1, 0}, 45}},
                             {4, {{0, 0, 34}, {0, 0, -1}, {0, 1, 0}, 45}}});
  for (const CameraPath* p : {&swap, &flip, &overshoot})
    for (int f = -1; f <= 5; ++f) EXPECT_EQ(camera_problem(p->at(f)), "") << "frame " << f;
  // Where the spline is fine it is used as before: constant speed stays linear.
  const CameraPath line = CameraPath::keyframes(
      {{0, {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45}}, {10, {{10, 0, 5}, {10, 0, 0}, {0, 1, 0}, 45}}});
  EXPECT_NEAR(line.at(3).eye.x, 3.0f, 1e-5f);
}

TEST(CameraInput, OrbitPeriodsThatWouldGiveNanAreRefused) {
  const Camera base{{0, 1, 4}, {0, 1, 0}, {0, 1, 0}, 40};
  for (float period : {0.0f, 1e-45f, 1e-20f, 1e-4f, -5.0f, float(INFINITY), float(NAN)})
    EXPECT_THROW(CameraPath::orbit(base, period), InputError) << period;
  EXPECT_THROW(CameraPath::orbit({{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 40}, 10), InputError);
  for (float period : {1e-3f, 0.7f, 1e30f}) {
    const CameraPath p = CameraPath::orbit(base, period);
    for (int f : {0, 1, 7, 1000, 2147483647})
      EXPECT_EQ(camera_problem(p.at(f)), "") << "period " << period << " frame " << f;
  }
}

// A base camera whose up is not vertical: the up vector turns with the eye, so no frame
// looks along it.
TEST(CameraInput, OrbitTurnsTheUpVectorWithTheEye) {
  const CameraPath p = CameraPath::orbit({{0, 0, 5}, {0, 0, 0}, {1, 0, 0}, 40}, 4);
  for (int f = 0; f < 8; ++f) {
    const Camera c = p.at(f);
    EXPECT_EQ(camera_problem(c), "") << "frame " << f;
    EXPECT_NEAR(dot(c.up, c.target - c.eye), 0.0f, 1e-4f) << "frame " << f;
  }
}

}  // namespace camera_input_test
}  // namespace multiray
