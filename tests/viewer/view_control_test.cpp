// The viewer's page messages and mouse camera, without a server.
#include <gtest/gtest.h>

#include <cmath>

#include "app/viewer/view_control.h"
#include "core/error.h"
#include "engine/orbit_camera.h"

namespace multiray::app::viewer {
namespace view_control_test {

TEST(ViewControl, GoodMessagesParse) {
  Command c = parse_command(R"({"type":"orbit","dx":10,"dy":-5})", 1);
  EXPECT_EQ(c.kind, Command::Kind::Orbit);
  EXPECT_FLOAT_EQ(c.x, 10);
  EXPECT_FLOAT_EQ(c.y, -5);
  c = parse_command(R"({"type":"zoom","factor":0.5})", 1);
  EXPECT_EQ(c.kind, Command::Kind::Zoom);
  c = parse_command(R"({"type":"balancer","spec":"queue:tile=32"})", 1);
  EXPECT_EQ(c.spec, "queue:tile=32");
  c = parse_command(R"({"type":"view","index":8})", 9);
  EXPECT_EQ(c.view, 8);
  EXPECT_EQ(parse_command(R"({"type":"reset"})", 1).kind, Command::Kind::Reset);
  c = parse_command(R"({"type":"look","yaw":-30,"pitch":12.5})", 1);
  EXPECT_EQ(c.kind, Command::Kind::Look);
  EXPECT_FLOAT_EQ(c.x, -30);
  EXPECT_FLOAT_EQ(c.y, 12.5f);
}

// The page's denoise toggle: each of --denoise's values, and nothing else.
TEST(ViewControl, DenoiseTakesTheMethodsOfDenoiseOnly) {
  for (const DenoiseMethodInfo& m : denoise_methods()) {
    const Command c =
        parse_command(std::string(R"({"type":"denoise","method":")") + m.name + "\"}", 1);
    EXPECT_EQ(c.kind, Command::Kind::Denoise) << m.name;
    EXPECT_EQ(c.denoise, m.choice) << m.name;
  }
  for (const char* bad :
       {R"({"type":"denoise"})", R"({"type":"denoise","method":1})",
        R"({"type":"denoise","method":"oidn"})", R"({"type":"denoise","method":"SVGF"})",
        R"({"type":"denoise","method":""})"})
    EXPECT_THROW(parse_command(bad, 1), InputError) << bad;
}

TEST(ViewControl, BadMessagesAreRefusedInOneLine) {
  for (const char* bad : {"",
                          "{",
                          "[1]",
                          "null",
                          "42",
                          R"({"dx":1})",
                          R"({"type":7})",
                          R"({"type":"jump"})",
                          R"({"type":"orbit","dx":1})",
                          R"({"type":"orbit","dx":"1","dy":0})",
                          R"({"type":"orbit","dx":1e309,"dy":0})",
                          R"({"type":"orbit","dx":400,"dy":0})",
                          R"({"type":"pan","dx":0,"dy":11})",
                          R"({"type":"zoom","factor":0})",
                          R"({"type":"zoom","factor":-1})",
                          R"({"type":"balancer"})",
                          R"({"type":"balancer","spec":""})",
                          R"({"type":"view","index":9})",
                          R"({"type":"view","index":-1})",
                          R"({"type":"look","yaw":0})",
                          R"({"type":"look","yaw":361,"pitch":0})",
                          R"({"type":"look","yaw":0,"pitch":-181})"}) {
    try {
      parse_command(bad, 9);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW(parse_command(std::string(5000, ' '), 1), InputError);
}

TEST(ViewControl, OrbitKeepsTheDistanceAndPanMovesTheTarget) {
  Camera base;
  base.eye = {0, 1, 5}, base.target = {0, 1, 0};
  OrbitCamera cam(base, {0, 1, 0});
  const Camera start = cam.camera();
  EXPECT_NEAR(length(start.eye - base.eye), 0, 1e-4);
  cam.orbit(90, 0);
  const Camera turned = cam.camera();
  EXPECT_NEAR(length(turned.eye - turned.target), 5, 1e-4);
  EXPECT_GT(length(turned.eye - start.eye), 1);
  cam.orbit(0, 500);  // clamped below the pole
  EXPECT_LT(dot(normalize(cam.camera().eye - cam.camera().target), Vec3{0, 1, 0}), 1.0f);
  cam.pan(0.5f, 0);
  EXPECT_GT(length(cam.camera().target - base.target), 0.1);
  cam.zoom(0.5f);
  EXPECT_NEAR(length(cam.camera().eye - cam.camera().target), 2.5, 1e-4);
  cam.zoom(1e-9f);  // clamped
  EXPECT_GT(length(cam.camera().eye - cam.camera().target), 0);
  cam.reset();
  EXPECT_NEAR(length(cam.camera().eye - base.eye), 0, 1e-4);
}

// A device turned in augmented reality turns the view about the eye: the eye stays, the
// view direction turns by the angles given (absolute, not summed), and reset undoes it.
TEST(ViewControl, LookTurnsTheViewAboutTheEye) {
  Camera base;
  base.eye = {0, 1, 5}, base.target = {0, 1, 0};
  OrbitCamera cam(base, {0, 1, 0});
  const auto dir = [&] { return normalize(cam.camera().target - cam.camera().eye); };
  cam.look(90, 0);
  EXPECT_NEAR(length(cam.camera().eye - base.eye), 0, 1e-4);
  EXPECT_NEAR(dot(dir(), Vec3{0, 0, -1}), 0, 1e-4);  // a quarter turn from looking along -z
  EXPECT_NEAR(dir().y, 0, 1e-4);
  cam.look(90, 0);  // the same orientation again: no further turn
  EXPECT_NEAR(dot(dir(), Vec3{0, 0, -1}), 0, 1e-4);
  cam.look(0, 30);  // tilted up by 30 degrees
  EXPECT_NEAR(dir().y, std::sin(30 * M_PI / 180), 1e-4);
  EXPECT_NEAR(length(cam.camera().eye - base.eye), 0, 1e-4);
  cam.reset();
  EXPECT_NEAR(dot(dir(), Vec3{0, 0, -1}), 1, 1e-4);
}

}  // namespace view_control_test
}  // namespace multiray::app::viewer
