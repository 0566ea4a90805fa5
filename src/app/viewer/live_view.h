// `multiray view`: a frame observer that streams every finished frame to the browsers
// connected to its web server, and turns their messages into camera moves, balancer
// switches and view choices for the session (issue "Live viewer").
//
// Rendering never waits on a browser: on_frame() only keeps the newest frame and wakes the
// sender thread, which encodes it (JPEG; PNG with alpha for an RGBA layer) and queues it with its
// measurements for every client (web_server.h: each client's queue keeps the newest frame only);
// frames that arrive while it is busy replace the one waiting (dropped, counted). Camera moves go
// through Session::set_camera (thread-safe); a balancer switch is applied by on_frame,
// between frames, on the session's thread. The denoiser (view_denoise.h) is chosen by the
// page and set for each frame in before_frame.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/viewer/listen_address.h"
#include "app/viewer/motion.h"
#include "app/viewer/view_control.h"
#include "app/viewer/view_denoise.h"
#include "app/viewer/web_server.h"
#include "core/image.h"
#include "engine/orbit_camera.h"
#include "engine/refinement.h"
#include "engine/session.h"

namespace multiray {
class VolumeRun;
}

namespace multiray::app::viewer {

struct LiveViewOptions {
  std::shared_ptr<VolumeRun> volume;  // volumes: the transfer functions and targeting
  ListenAddress bind{"127.0.0.1", false, true};
  int port = 8080;
  int max_clients = 16;  // open WebSockets at once (web_server.h)
  Display display;
  // Meter the first streamed frame (core/exposure.h) and hold that exposure, instead of
  // display.exposure_ev as given (--exposure auto).
  bool meter_exposure = false;
  int jpeg_quality = 85;
  // Progressive refinement (refinement.h): the session renders `frame_spp` samples a frame
  // and the page is shown the mean of the frames since the last change, up to
  // `refine_spp`. 0: every frame is shown as rendered (volumes).
  int frame_spp = 1;
  int refine_spp = 0;
  // Image scale of frames begun while the camera moves (motion.h); 1: full size always.
  double move_scale = 1.0;
  // A --distributed run: each worker builds its own transfer function from --tf, so the
  // page may not switch it (the master's alone would change).
  bool distributed = false;
  // Augmented reality (--ar, docs/ar.md): the page shows the device's camera behind the
  // frames (RGBA, from --ground's shadow catcher) and turns the view with the device.
  bool ar = false;
  // The denoiser to start with (--denoise; view_denoise.h), and whether the run can record
  // the feature buffers it needs (Run::can_record_features): when it cannot, the choice
  // must be none and the page may not turn it on. The frames record feature buffers while
  // the choice is not none.
  DenoiseChoice denoise = DenoiseChoice::none;
  bool can_denoise = false;
};

class LiveView : public FrameObserver {
 public:
  // `session` must outlive the view; `camera` starts at the session's camera.
  LiveView(Session& session, OrbitCamera camera, std::vector<std::string> device_names,
           LiveViewOptions options);
  ~LiveView();

  void before_frame(int frame, const FrameInput& input) override;
  void on_frame(const std::shared_ptr<const FrameResult>& result) override;
  int port() const { return server_->port(); }
  // Frames the sender skipped because newer ones finished while it encoded.
  uint64_t frames_dropped() const { return dropped_; }
  // The server, whose receive() takes a client's message the way a socket delivers it.
  WebServer& server() { return *server_; }

 private:
  void send_loop();
  void handle(int client, const std::string& text);
  // Volumes: a transfer function or target from the page; an error message or "".
  std::string volume_command(const Command& c);
  std::string hello() const;
  // How a frame was begun: its camera (set_camera may have moved it since) and where its
  // samples start in the sequence they continue (ViewSetup::first_sample; 0: its own).
  struct Begun {
    Camera camera;
    uint32_t first_sample = 0;
  };
  // What the page is shown of a frame: the image, its samples per pixel (0: as rendered),
  // the filter that made it, and how the frame was begun.
  struct Shown {
    std::shared_ptr<const Framebuffer> image;
    int samples = 0;
    DenoiseMethod denoised = DenoiseMethod::none;
    Begun begun;
  };
  // Sent as "camera": {"eye", "target"}, "first_sample", "denoise" (the filter's name) and
  // "shown_hash" (image_hash of the image shown; "image_hash" is the frame's as rendered).
  std::string frame_json(const FrameResult& r, int view, const std::string& balancer,
                         const Shown& shown) const;
  // The image of `r`'s view `view` to show (refined, or as rendered; denoised or not), for
  // a frame begun as `begun` (null: unknown); on the session's thread.
  Shown shown_image(const FrameResult& r, int view, const Begun* begun);

  Session& session_;
  std::vector<std::string> device_names_;
  LiveViewOptions options_;
  std::mutex camera_mutex_;
  OrbitCamera camera_;
  std::mutex mutex_;  // guards the fields below
  std::condition_variable wake_;
  std::shared_ptr<const FrameResult> pending_;
  Shown pending_shown_;  // what to show of pending_
  int pending_view_ = 0;
  std::map<int, Begun> frame_begun_;  // frames begun and not yet finished
  // On the session's thread only: the refinement, the denoiser's state and the camera of
  // the frame begun before.
  std::unique_ptr<Refinement> refinement_;
  ViewDenoise denoise_;
  std::optional<Camera> previous_camera_;
  std::shared_ptr<MotionClock> motion_;  // null: frames at full size while moving
  std::string pending_balancer_;         // the spec that planned pending_
  double target_request_ = 0;            // ms; 0: none pending
  std::mutex volume_mutex_;  // VolumeRun is used from the session's and civetweb's threads
  std::shared_ptr<const VolumeStyle> style_override_;  // the page's transfer function
  std::string balancer_request_;
  int view_ = 0;
  bool stop_ = false;
  std::atomic<uint64_t> dropped_{0};
  std::unique_ptr<WebServer> server_;
  std::thread sender_;
};

// The page served at "/" (HTML, CSS and script in one file), and its augmented-reality
// script (page_ar.cpp).
const std::string& viewer_page();
const std::string& ar_page_script();

}  // namespace multiray::app::viewer
