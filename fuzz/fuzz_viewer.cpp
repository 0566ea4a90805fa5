// Fuzz target of the live viewer's handling of what a client sends (src/app/viewer): the
// input is the bytes a client writes on its WebSocket after the handshake, raw RFC 6455
// frames, fed in chunks through WebServer::receive() — the path the server's read loop
// takes for a connected client: the frame decoder (ws_frames.h), then each text message into
// LiveView's dispatch (parse_command, the balancer spec check, camera moves, the streamed
// view). One frame is then rendered through the LiveView as `multiray view` does, so a
// balancer switch is applied and the camera the messages made is traced.
//
// Checks: no exception escapes receive() (on civetweb's thread one would end the viewer);
// the decoder never holds more than one frame and one message (under 14 + 4096 bytes each);
// every control frame answered is at most 125 bytes; every camera the session renders passes
// camera_problem(), and every pixel is finite. Sanitizer reports and crashes are findings as
// in every target.
//
// Input: byte 0 is the chunk size the bytes arrive in (0: ws::kReadBytes), the rest the
// client's bytes. When the server closes the connection (a close frame, a refusal), the
// rest of the input starts a new connection. Each input starts from the starting camera, the
// `uniform` balancer and view 0, sent as messages too.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "app/viewer/live_view.h"
#include "app/viewer/web_server.h"
#include "app/viewer/ws_frames.h"
#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/frame_views.h"
#include "engine/session.h"
#include "fuzz_support.h"
#include "render/scene_cache.h"
#include "scene/builders.h"
#include "scene/camera_check.h"
#include "scene/camera_path.h"
#include "scene/camera_rig.h"

namespace {

using namespace multiray;
using app::viewer::LiveView;

constexpr int kClient = 1;  // not connected: replies to it are dropped

// Checks what the session renders, then hands it to the viewer.
struct Checked : FrameObserver {
  LiveView* view = nullptr;
  void before_frame(int frame, const FrameInput& input) override {
    for (const ViewSetup& v : input.views)
      if (const std::string p = camera_problem(v.camera); !p.empty())
        fuzz::fail("the messages made a camera the session renders: " + p);
    view->before_frame(frame, input);
  }
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    for (const Framebuffer& img : r->images)
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          const Vec3& p = img.at(x, y);
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fuzz::fail("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                       ") is not finite");
        }
    view->on_frame(r);
  }
};

// The viewer of `multiray view` on the Cornell box, 8x6, one CPU device: made once and kept
// to the end of the process (its server and sender threads run meanwhile).
struct Viewer {
  const Scene* scene = new Scene(make_cornell_box());
  SceneCache* cache = new SceneCache(*scene);
  CpuDevice* device = new CpuDevice(*cache, CpuDeviceOptions{}, "cpu");
  Session* session = nullptr;
  LiveView* view = nullptr;
  Checked check;
  int frame = 0;
  Viewer() {
    const Camera camera = scene->default_camera(float(fuzz::kRenderWidth) / fuzz::kRenderHeight);
    std::vector<std::unique_ptr<balance::Balancer>> lanes;
    lanes.push_back(balance::make_balancer("uniform", 1));
    RenderSettings settings;
    settings.spp = 1;
    settings.max_bounces = 2;
    session =
        new Session({device}, std::move(lanes),
                    FrameViews(CameraRig::single(), fuzz::kRenderWidth, fuzz::kRenderHeight, {}),
                    CameraPath::fixed(camera), settings);
    app::viewer::LiveViewOptions options;
    options.port = 0;  // loopback, any free port; nothing connects
    options.max_clients = 1;
    view = new LiveView(*session, OrbitCamera(camera, Vec3(0, 1, 0)), {"cpu"}, options);
    check.view = view;
  }
  void text(const std::string& message) {
    app::viewer::ws::Decoder d;  // a masked text frame, key 0
    std::string frame = {char(0x81), char(0x80 | message.size()), 0, 0, 0, 0};
    view->server().receive(kClient, d, frame + message);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Viewer* viewer = new Viewer();
  viewer->text(R"({"type":"reset"})");
  viewer->text(R"({"type":"balancer","spec":"uniform"})");
  viewer->text(R"({"type":"view","index":0})");
  namespace ws = app::viewer::ws;
  const size_t chunk = size > 0 && data[0] ? data[0] : ws::kReadBytes;
  ws::Decoder decoder;
  for (size_t at = 1; at < size; at += chunk) {
    const std::string_view bytes(reinterpret_cast<const char*>(data + at),
                                 std::min(chunk, size - at));
    app::viewer::WebServer::Answer answer;
    try {
      answer = viewer->view->server().receive(kClient, decoder, bytes);
    } catch (const std::exception& e) {
      fuzz::fail(std::string("an exception escaped the message handler: ") + e.what());
    }
    if (decoder.pending.size() >= 14 + ws::kMaxMessageBytes ||
        decoder.message.size() > ws::kMaxMessageBytes)
      fuzz::fail("the decoder holds " + std::to_string(decoder.pending.size()) + " + " +
                 std::to_string(decoder.message.size()) + " bytes, more than one frame");
    for (const auto& [opcode, payload] : answer.frames)
      if (payload.size() > ws::kMaxControlBytes)
        fuzz::fail("a control frame of " + std::to_string(payload.size()) + " bytes answered");
    if (answer.close) decoder = ws::Decoder{};  // the client connects again
  }
  if (viewer->session->run(viewer->frame++, 1, viewer->check) != 1)
    fuzz::fail("the session did not complete the frame");
  return 0;
}
