// The live viewer as a user drags (issue 33): starts `multiray view ARGS`, connects as the
// page does, sends an orbit step every 20 ms (a mouse at 50 Hz) for SECONDS, and counts
// the frames (JPEGs) that reach the client; then stops moving and times how long the
// picture takes to converge (a full-size frame with spp = refine_spp). One JSON line on stdout.
// bench/viewer_fps.sh runs it; a timing, so only on a quiet machine.
//
//   viewer_fps SECONDS [view options...]
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "viewer_process.h"
#include "ws_client.h"

int main(int argc, char** argv) {
  using clock = std::chrono::steady_clock;
  if (argc < 2) {
    std::fprintf(stderr, "usage: viewer_fps SECONDS [view options...]\n");
    return 2;
  }
  const double seconds = std::atof(argv[1]);
  std::string args;
  for (int i = 2; i < argc; ++i) args += std::string(" ") + argv[i];
  mg_init_library(MG_FEATURES_WEBSOCKET);
  multiray::testing::ViewerProcess viewer(args);
  if (viewer.port() <= 0) {
    std::fprintf(stderr, "viewer_fps: multiray view did not start\n");
    return 1;
  }
  multiray::testing::Client client(viewer.port());
  if (!client.connected() || client.wait_type("frame").is_null()) {
    std::fprintf(stderr, "viewer_fps: no frame arrived\n");
    return 1;
  }
  // Dragging: an orbit step every 20 ms; frames counted as their JPEGs arrive.
  const size_t before = client.jpegs();
  const auto start = clock::now();
  while (std::chrono::duration<double>(clock::now() - start).count() < seconds) {
    client.send(R"({"type":"orbit","dx":1,"dy":0})");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const double drag_s = std::chrono::duration<double>(clock::now() - start).count();
  const size_t dragged = client.jpegs() - before;
  // Still: the time to a converged picture (the frames in flight still show the last move).
  const auto still = clock::now();
  const nlohmann::json done = client.wait(
      [](const nlohmann::json& j) {
        return j.value("type", "") == "frame" && j.value("refine_spp", 0) > 0 &&
               j.value("spp", 0) >= j.value("refine_spp", 0) &&
               j.value("image_scale", 1.0) == 1.0;  // full size, not the hold's smaller frames
      },
      std::chrono::seconds(120));
  const double converge_s = std::chrono::duration<double>(clock::now() - still).count();
  std::printf("{\"drag_s\": %.2f, \"frames\": %zu, \"drag_fps\": %.2f, \"converge_s\": %.2f}\n",
              drag_s, dragged, double(dragged) / drag_s, done.is_null() ? -1.0 : converge_s);
  viewer.stop();
  return 0;
}
