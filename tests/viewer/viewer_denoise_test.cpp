// `multiray view --denoise` (issue 52) over its WebSocket, as the page talks to it: frames
// begun while the camera moves are sent denoised (the image shown is not the one
// rendered), the page's toggle turns the denoiser off between frames, and a bad value is
// refused in one line before anything is served.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"
#include "viewer_process.h"
#include "ws_client.h"

namespace viewer_denoise_test {

using multiray::testing::Client;
using multiray::testing::ViewerProcess;

const char* kArgs = "--res 64x36 --spp 1 --bounces 2 --devices cpu:threads=1,cpu:threads=1";

bool frame_with(const nlohmann::json& j, const std::string& denoise) {
  return j.value("type", "") == "frame" && j.value("denoise", "") == denoise;
}

TEST(ViewerDenoise, SendsDenoisedFramesWhileTheCameraMovesAndFollowsTheToggle) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  ViewerProcess viewer(std::string("--denoise svgf ") + kArgs);
  ASSERT_GT(viewer.port(), 0);
  Client c(viewer.port());
  ASSERT_TRUE(c.connected()) << c.error();
  const nlohmann::json hello = c.wait_type("hello");
  ASSERT_FALSE(hello.is_null());
  EXPECT_EQ(hello["denoise"], "svgf");
  EXPECT_EQ(hello["can_denoise"], true);
  // Moves: each frame begun after one is filtered by the session's svgf and sent so.
  int denoised = 0;
  for (int move = 0; move < 3; ++move) {
    c.send(R"({"type":"orbit","dx":15,"dy":0})");
    const nlohmann::json f = c.wait([](const nlohmann::json& j) { return frame_with(j, "svgf"); });
    ASSERT_FALSE(f.is_null()) << "no svgf frame after a move";
    EXPECT_NE(f["shown_hash"], f["image_hash"]) << "the raw frame was sent: " << f.dump();
    denoised += f["shown_hash"] != f["image_hash"];
  }
  EXPECT_EQ(denoised, 3);
  // A still camera's refined image is filtered spatially.
  EXPECT_FALSE(c.wait([](const nlohmann::json& j) { return frame_with(j, "atrous"); }).is_null());
  // Off: the frame begun after a move is sent as rendered (a few moves, in case the
  // sender skipped that one for a newer frame, which would show the same image).
  c.send(R"({"type":"denoise","method":"none"})");
  nlohmann::json off;
  for (int move = 0; move < 5 && off.is_null(); ++move) {
    c.send(R"({"type":"orbit","dx":15,"dy":0})");
    off = c.wait(
        [](const nlohmann::json& j) {
          return frame_with(j, "none") && j["shown_hash"] == j["image_hash"];
        },
        std::chrono::seconds(5));
  }
  EXPECT_FALSE(off.is_null()) << "the toggle did not turn the denoiser off";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

TEST(ViewerDenoise, BadValuesAreRefusedInOneLine) {
  for (const std::string bad : {"--denoise svfg", "--integrator ao --denoise svgf"}) {
    const std::string args = "view --port 0 --max-frames 1 --res 16x8 --spp 1 " + bad;
    const auto r = multiray::testing::run_cli(MULTIRAY_BIN, args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.out;
    EXPECT_NE(r.out.find("--denoise"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out;
  }
}

}  // namespace viewer_denoise_test
