// Fuzz target of the live viewer's handling of what a client sends (src/app/viewer): the
// input becomes WebSocket frames that go through WebServer::receive(), the path civetweb's
// data callback takes for a connected client, into LiveView's dispatch (parse_command, the
// balancer spec check, camera moves, the streamed view), and one frame is then rendered
// through the LiveView as `multiray view` does, so a balancer switch is applied and the
// camera the messages made is traced.
//
// Checks: no exception escapes receive() (on civetweb's thread one would end the viewer),
// every camera the session renders passes camera_problem(), and every pixel is finite.
// Sanitizer reports and crashes are findings as in every target.
//
// Input: frames, each 1 byte of WebSocket FIN and opcode bits, a 2-byte payload length
// (little endian; up to 65535, so the 4096-byte limit is crossed), then the payload, cut
// short where the input ends. Each input starts from the starting camera, the `uniform`
// balancer and view 0, sent as messages too.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "app/viewer/live_view.h"
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
    view->server().receive(kClient, 0x80 | 1, message.data(), message.size());
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Viewer* viewer = new Viewer();
  viewer->text(R"({"type":"reset"})");
  viewer->text(R"({"type":"balancer","spec":"uniform"})");
  viewer->text(R"({"type":"view","index":0})");
  for (size_t at = 0; at + 3 <= size;) {
    const int bits = data[at];
    const size_t len = std::min<size_t>(data[at + 1] | size_t(data[at + 2]) << 8, size - at - 3);
    const char* payload = reinterpret_cast<const char*>(data + at + 3);
    try {
      viewer->view->server().receive(kClient, bits, payload, len);
    } catch (const std::exception& e) {
      fuzz::fail(std::string("an exception escaped the message handler: ") + e.what());
    }
    at += 3 + len;
  }
  if (viewer->session->run(viewer->frame++, 1, viewer->check) != 1)
    fuzz::fail("the session did not complete the frame");
  return 0;
}
