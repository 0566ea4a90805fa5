// `multiray view` over its WebSocket, as the page talks to it: frames arrive (JSON, then a
// JPEG), the camera and the balancer follow commands, several clients watch at once, and
// malformed or hostile messages get error replies while the server keeps rendering.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iterator>
#include <mutex>
#include <random>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "viewer_process.h"
#include "ws_client.h"

namespace viewer_server_test {

using multiray::testing::Client;

const char* kArgs = "--res 64x36 --spp 1 --bounces 2 --devices cpu:threads=1,cpu:threads=1";

TEST(ViewerServer, StreamsFramesAndFollowsCommands) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  multiray::testing::ViewerProcess viewer(kArgs);
  ASSERT_GT(viewer.port(), 0);
  Client a(viewer.port()), b(viewer.port());
  ASSERT_TRUE(a.connected() && b.connected());
  const nlohmann::json hello = a.wait_type("hello");
  ASSERT_FALSE(hello.is_null());
  EXPECT_EQ(hello["devices"].size(), 2u);
  const nlohmann::json first = a.wait_type("frame");
  ASSERT_FALSE(first.is_null());
  EXPECT_EQ(first["width"], 64);
  EXPECT_EQ(first["devices"].size(), 2u);
  EXPECT_FALSE(first["items"].empty());
  EXPECT_FALSE(b.wait_type("frame").is_null()) << "a second client sees frames too";
  ASSERT_FALSE(a.wait_type("frame").is_null());
  EXPECT_GT(a.jpegs(), 0u) << "the first frame's JPEG came before the second frame";

  // The camera follows an orbit: a later frame differs.
  const std::string before = a.wait_type("frame")["image_hash"];
  a.send(R"({"type":"orbit","dx":40,"dy":10})");
  const nlohmann::json moved = a.wait([&](const nlohmann::json& j) {
    return j.value("type", "") == "frame" && j.value("image_hash", "") != before;
  });
  EXPECT_FALSE(moved.is_null()) << "the camera did not move";
  // The balancer switches between frames.
  a.send(R"({"type":"balancer","spec":"queue:tile=16"})");
  const nlohmann::json switched = a.wait([](const nlohmann::json& j) {
    return j.value("type", "") == "frame" && j.value("balancer", "").rfind("queue", 0) == 0;
  });
  EXPECT_FALSE(switched.is_null()) << "the balancer did not switch";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

#ifdef MULTIRAY_MPIEXEC
// `multiray render`'s hash of frame `frame` with the viewer's settings (one process).
std::string rendered_hash(const std::string& settings, int frame) {
  const std::string dir = ::testing::TempDir() + "/viewer_distributed_render";
  const std::string cmd = std::string(MULTIRAY_BIN) + " render " + settings + " --frames " +
                          std::to_string(frame + 1) + " -o " + dir + " --overwrite -q";
  if (std::system(cmd.c_str()) != 0) return "render failed";
  std::ifstream in(dir + "/stats.json");
  return nlohmann::json::parse(in).at("frames").at(size_t(frame)).at("image_hash");
}

// A --distributed run watched and steered (issue 33): the master serves the page, the
// workers render; its frames are one process's to the bit (the split never changes the
// pixels), the camera follows the page, and a Ctrl-C stops every rank.
TEST(ViewerServer, WatchesAndSteersADistributedRun) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  const std::string settings = "--res 64x36 --spp 1 --bounces 2";
  multiray::testing::ViewerProcess viewer(
      settings + " --frame-spp 1 --distributed 2> " + ::testing::TempDir() +
          "/viewer_distributed.err",
      std::string(MULTIRAY_MPIEXEC) + " --oversubscribe --allow-run-as-root -np 3 ");
  ASSERT_GT(viewer.port(), 0);
  Client a(viewer.port());
  ASSERT_TRUE(a.connected());
  const nlohmann::json hello = a.wait_type("hello");
  ASSERT_FALSE(hello.is_null());
  EXPECT_EQ(hello["devices"].size(), 2u);  // the two workers
  const nlohmann::json first = a.wait_type("frame");
  ASSERT_FALSE(first.is_null());
  const std::string before = first["image_hash"];
  a.send(R"({"type":"orbit","dx":40,"dy":10})");
  const nlohmann::json moved = a.wait([&](const nlohmann::json& j) {
    return j.value("type", "") == "frame" && j.value("image_hash", "") != before;
  });
  EXPECT_FALSE(moved.is_null()) << "the workers did not follow the camera";
  const int code = viewer.stop();
  EXPECT_NE(code, -1) << "a rank ignored Ctrl-C";
  std::ifstream err_file(::testing::TempDir() + "/viewer_distributed.err");
  const std::string err((std::istreambuf_iterator<char>(err_file)), {});
  EXPECT_EQ(err.find("signal"), std::string::npos) << "a rank crashed on the way out";
  // A run that ends by itself (--max-frames): the master releases the workers, and every
  // rank exits 0.
  const std::string ended = std::string(MULTIRAY_MPIEXEC) +
                            " --oversubscribe --allow-run-as-root -np 3 " + MULTIRAY_BIN +
                            " view --port 0 --max-frames 3 " + settings +
                            " --distributed > /dev/null 2>&1";
  EXPECT_EQ(std::system(ended.c_str()), 0) << ended;
  EXPECT_EQ(before, rendered_hash(settings, first["frame"].get<int>()))
      << "the workers' frame differs from one process's";
}
#endif

// A frame message of the refined image at --spp 16, rendered at full size.
bool converged_full_size(const nlohmann::json& j) {
  return j.value("type", "") == "frame" && j.value("spp", 0) == 16 &&
         j.value("image_scale", 0.0) == 1.0;
}

// Progressive refinement (issue 33): each frame has --frame-spp samples; while the camera
// stands, the page gets the mean of the frames since it stopped, up to --spp, and a move
// starts again from one frame.
TEST(ViewerServer, RefinesWhileStillAndStartsAgainOnAMove) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  multiray::testing::ViewerProcess viewer(
      "--res 64x36 --spp 16 --frame-spp 1 --devices cpu:threads=1");
  ASSERT_GT(viewer.port(), 0);
  Client c(viewer.port());
  ASSERT_TRUE(c.connected());
  const nlohmann::json still = c.wait(converged_full_size);
  ASSERT_FALSE(still.is_null()) << "never refined to --spp";
  EXPECT_EQ(still["refine_spp"], 16);
  // Progressive sampling: the frames being averaged continue one sample sequence, so the
  // sixteenth of them starts at sample 15 (a frame of its own starts at 0).
  EXPECT_GE(still.value("first_sample", 0), 15) << still.dump();
  // Every frame has its own samples (so its own hash): the sign of a restart is a frame
  // shown with fewer than --spp samples.
  c.send(R"({"type":"orbit","dx":30,"dy":0})");
  const nlohmann::json moved = c.wait([](const nlohmann::json& j) {
    return j.value("type", "") == "frame" && j.value("spp", 16) < 16;
  });
  EXPECT_FALSE(moved.is_null()) << "a move did not start the refinement again";
  // While the camera moves, frames are rendered at --move-scale (default 0.5).
  nlohmann::json smaller;
  for (int i = 0; i < 100 && smaller.is_null(); ++i) {
    c.send(R"({"type":"orbit","dx":1,"dy":0})");
    smaller = c.wait(
        [](const nlohmann::json& j) {
          return j.value("type", "") == "frame" && j.value("image_scale", 1.0) == 0.5;
        },
        std::chrono::seconds(0));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_FALSE(smaller.is_null()) << "no frame at --move-scale while the camera moved";
  EXPECT_FALSE(c.wait(converged_full_size).is_null()) << "did not refine again after the move";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// The still image after a drag. Frames begun within kMotionHoldSeconds of the last move are
// rendered at --move-scale with the camera where it stopped, the same camera as the still
// frames after them; the session starts the sample sequence again at the first full-size
// frame. The refinement must too: the first full-size frame under a camera shows its own
// samples only (spp 1), and the converged image is the sequence's 16 frames (the last of
// them starts at sample 15). Until 2026-12-04 the frames rendered smaller were averaged in:
// at this size the hold's 16 half-size frames made the "converged" image, and the full-size
// frames after them were ignored.
TEST(ViewerServer, AStillImageAfterADragHoldsNoFrameRenderedSmaller) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  multiray::testing::ViewerProcess viewer(
      "--res 64x36 --spp 16 --frame-spp 1 --devices cpu:threads=1 --denoise none");
  ASSERT_GT(viewer.port(), 0);
  Client c(viewer.port());
  ASSERT_TRUE(c.connected());
  const nlohmann::json start = c.wait(converged_full_size);
  ASSERT_FALSE(start.is_null());
  for (int i = 0; i < 5; ++i) {
    c.send(R"({"type":"orbit","dx":3,"dy":0})");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  nlohmann::json first_full, smaller;  // under the camera where the moves ended
  // By time, not by frames: at this size a frame takes well under a millisecond, and the
  // hold alone makes hundreds of them.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    const nlohmann::json f = c.wait_type("frame");
    ASSERT_FALSE(f.is_null());
    if (f["camera"] == start["camera"]) continue;  // begun before the moves
    if (f.value("image_scale", 1.0) < 1.0) {
      smaller = f;
      first_full = nullptr;  // the camera may still move
      continue;
    }
    if (first_full.is_null() || f["camera"] != first_full["camera"]) first_full = f;
    if (converged_full_size(f)) {
      EXPECT_EQ(first_full.value("spp", 0), 1) << "the first full-size frame: " << first_full;
      EXPECT_GE(f.value("first_sample", 0), 15) << f.dump();
      break;
    }
  }
  EXPECT_FALSE(smaller.is_null()) << "no frame rendered smaller while the camera moved";
  EXPECT_FALSE(first_full.is_null()) << "no full-size frame after the moves";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// Fuzz-style: malformed, out-of-range and random messages each get an error reply (or are
// ignored), and the server keeps streaming frames afterwards. Random bytes are ASCII: text
// that is not UTF-8, or a message over 4096 bytes, closes the connection with 1007 or 1009
// (RFC 6455 §7.4.1, issue 53; tests/viewer/ws_protocol_test.cpp).
TEST(ViewerServer, SurvivesHostileMessages) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  multiray::testing::ViewerProcess viewer(kArgs);
  ASSERT_GT(viewer.port(), 0);
  Client c(viewer.port());
  ASSERT_TRUE(c.connected());
  ASSERT_FALSE(c.wait_type("frame").is_null());
  std::vector<std::string> bad = {"",
                                  "{",
                                  "[]",
                                  "null",
                                  R"({"type":"orbit","dx":1e999,"dy":0})",
                                  R"({"type":"zoom","factor":"big"})",
                                  R"({"type":"balancer","spec":"nonsense:x=1"})",
                                  R"({"type":"view","index":3})",
                                  R"({"type":"balancer","spec":"../../etc/passwd"})"};
  std::mt19937 rng(7);
  for (int i = 0; i < 200; ++i) {
    std::string s(size_t(rng() % 64), '\0');
    for (char& ch : s) ch = char(rng() % 128);
    bad.push_back(s);
  }
  for (const std::string& m : bad) c.send(m);
  c.send(std::string("\x01\x02\x03", 3), MG_WEBSOCKET_OPCODE_BINARY);
  const nlohmann::json error = c.wait_type("error");
  ASSERT_FALSE(error.is_null());
  EXPECT_FALSE(error["message"].get<std::string>().empty());
  EXPECT_FALSE(c.wait_type("frame").is_null()) << "the server stopped streaming";
  // A client that vanishes mid-stream does not stop the others.
  { Client gone(viewer.port()); }
  Client after(viewer.port());
  EXPECT_FALSE(after.wait_type("frame").is_null());
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// Volumes: the page's transfer-function presets and JSON change the picture; a name that
// is not a preset (a path, say) is refused, never opened; the frame-time target needs
// --adapt and is accepted with it.
TEST(ViewerServer, VolumeTransferFunctionsAndTarget) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  std::string bytes;  // a 24^3 ball of 200 in zeros
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        bytes.push_back(
            char((x - 12) * (x - 12) + (y - 12) * (y - 12) + (z - 12) * (z - 12) < 64 ? 200 : 0));
  const std::string raw = ::testing::TempDir() + "/viewer_ball.raw";
  std::ofstream(raw, std::ios::binary) << bytes;
  const std::string volume =
      raw + " --raw 24x24x24:uint8 --res 48x32 --devices cpu:threads=1,cpu:threads=1 ";
  {
    multiray::testing::ViewerProcess viewer(volume + "--tf angio");
    ASSERT_GT(viewer.port(), 0);
    Client c(viewer.port());
    const nlohmann::json hello = c.wait_type("hello");
    ASSERT_TRUE(hello.value("volume", false));
    const std::string before = c.wait_type("frame")["image_hash"];
    c.send(R"({"type":"tf","preset":"grey"})");
    EXPECT_FALSE(c.wait([&](const nlohmann::json& j) {
                    return j.value("type", "") == "frame" && j.value("image_hash", "") != before;
                  }).is_null());
    const std::string grey = c.wait_type("frame")["image_hash"];
    c.send(
        R"({"type":"tf","json":"{\"units\":\"fraction\",\"points\":[{\"value\":0,\"color\":[1,0,0],\"opacity\":0},{\"value\":1,\"color\":[1,0,0],\"opacity\":1}]}"})");
    EXPECT_FALSE(c.wait([&](const nlohmann::json& j) {
                    return j.value("type", "") == "frame" && j.value("image_hash", "") != grey;
                  }).is_null());
    for (const char* bad : {R"({"type":"tf","preset":"/etc/passwd"})",
                            R"({"type":"tf","json":"{"})", R"({"type":"target","ms":50})"}) {
      c.send(bad);
      EXPECT_FALSE(c.wait_type("error").is_null()) << bad;
    }
  }
  multiray::testing::ViewerProcess adapting(volume + "--adapt last-frame --target-ms 40");
  Client c(adapting.port());
  ASSERT_FALSE(c.wait_type("frame").is_null());
  c.send(R"({"type":"target","ms":20})");
  c.send(R"({"type":"orbit","dx":1e999})");  // then an error, to see the target had none
  const nlohmann::json error = c.wait_type("error");
  ASSERT_FALSE(error.is_null());
  EXPECT_EQ(error["message"].get<std::string>().find("targeting"), std::string::npos);
}

}  // namespace viewer_server_test
