// The one frame loop, used by `render`, `bench` (and the live viewer and the MPI master to
// come): for each frame, the views are made (camera path, or the camera the caller set),
// then every lane — one Engine, i.e. one balancer over the shared devices — renders the
// frame in turn, and the observer is handed each finished frame.
//
// Finished frames are handed over as shared_ptr<const FrameResult>. The session never
// writes into a result an observer still holds: it renders into a buffer nobody else
// references (double-buffered in the usual case, more buffers if an observer keeps frames
// longer), so an observer may pass a frame to another thread (an encoder, a web socket)
// while the next frame renders, with no data race.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "engine/background_job.h"
#include "engine/engine.h"
#include "engine/frame_denoiser.h"
#include "engine/frame_views.h"
#include "scene/camera_path.h"

namespace multiray {

// One lane's rendering of one frame.
struct FrameResult {
  size_t lane = 0;
  int frame = 0;
  FrameRecord record;
  std::vector<Framebuffer> images;  // every view at the output size
  // With a denoiser (Session::set_denoise), every view denoised (render/denoise.h), at the
  // output size, its time in record.denoise_ms; empty otherwise. `images` stay the raw
  // beauty. A frame rendered at a reduced image scale is filtered at the size it was
  // rendered and then enlarged (FrameDenoiser::apply_scaled).
  std::vector<Framebuffer> denoised;
  DenoiseMethod denoised_with = DenoiseMethod::none;  // what made `denoised`
  balance::Plan plan;                                 // what the balancer planned
  // What each device actually rendered (after pulls and steals), per device.
  std::vector<std::vector<balance::WorkItem>> rendered;
  balance::FrameStats stats;  // per-item measurements, as the balancer was told
  double sampling_ms = 0;     // host set-up of the frame's views (outside the frame time)
  // Reprojected sampling: the reference view and every view's map (null otherwise).
  std::shared_ptr<const ReprojectedFrame> reprojection;
};

class FrameObserver {
 public:
  virtual ~FrameObserver() = default;
  // Before any lane renders `frame` (e.g. a benchmark times each device alone here).
  virtual void before_frame(int /*frame*/, const FrameInput& /*input*/) {}
  // After lane `result->lane` finished frame `result->frame`. The result stays valid for as
  // long as the observer holds it.
  virtual void on_frame(const std::shared_ptr<const FrameResult>& result) = 0;
};

class Session {
 public:
  // Devices are shared by all lanes (which render one after the other) and must outlive
  // the session. One lane per balancer; at least one.
  Session(std::vector<Device*> devices, std::vector<std::unique_ptr<balance::Balancer>> lanes,
          FrameViews views, CameraPath path, RenderSettings settings);

  void set_perturbations(const std::vector<Perturbation>& p);
  // Gives every lane its own advisor (frame_advisor.h): make(lane), called once per lane
  // (null: none), or none at all when `make` is empty.
  void set_advisors(const std::function<std::unique_ptr<FrameAdvisor>(size_t lane)>& make);
  // The settings of the frame being rendered (after the schedule).
  const RenderSettings& settings() const { return settings_; }
  // Settings that change during a run (a transfer function switched at a given frame):
  // `at(frame, settings)` may change the settings of `frame` before any lane renders it.
  // Called on the thread that runs run().
  void set_settings_schedule(std::function<void(int, RenderSettings&)> at) {
    schedule_ = std::move(at);
  }

  // The camera of the following frames, instead of the path's: for interactive use.
  // Thread-safe; takes effect at the next frame. std::nullopt returns to the path.
  void set_camera(std::optional<Camera> camera);
  // The path of the following frames (and no camera set by set_camera any more).
  // Thread-safe; takes effect at the next frame.
  void set_camera_path(CameraPath path);
  // Progressive sampling, for a viewer that averages successive frames of a still camera
  // (engine/refinement.h): while the camera and the settings stay those of the frame
  // before, each frame's samples continue the sample sequence of the frame where they last
  // changed (ViewSetup::first_sample), so the mean of N frames of S samples is the image
  // of one render of N x S samples, as evenly spread. A frame after one rendered at less
  // than full quality (the viewer's smaller frames while the camera moves) begins a
  // sequence too, so the full-size frames a viewer averages start at sample 0, where the
  // sequence's blocks of 2^m are spread evenly. Uniform sampling only (adaptive, foveated
  // and reprojected frames begin their own sequence). Off by default: then every frame
  // begins its own. Call before run().
  void set_progressive(bool on) { progressive_ = on; }
  // Denoises every lane's frames after the gather (FrameResult::denoised), each lane with
  // a history of its own; DenoiseMethod::none: no denoiser. The frames must record feature
  // buffers (RenderSettings::feature_buffers), or they are passed through.
  // May be called at any time from any thread (a live viewer's toggle): the method is
  // taken up when a frame starts, after the observer's before_frame() (so a call from
  // there applies to that frame), and holds for all its lanes. A different method starts
  // every lane's history again (svgf's history from frames filtered otherwise, or not at
  // all, is not this method's); the same method again keeps it.
  void set_denoise(DenoiseMethod method) { denoise_request_ = method; }
  // The filter's parameters for every method (render/denoise.h; `--denoise-normal`). Call
  // before run().
  void set_denoise_params(const DenoiseParams& params) { denoise_params_ = params; }
  // The method of the frame being rendered (or of the last one).
  DenoiseMethod denoise() const { return denoise_; }
  // The denoiser beside the rendering: with one lane, frame N is filtered on a thread of
  // its own while frame N+1 renders, and the observer is handed frame N once both are
  // done (so one frame later than without; every frame still, in order, the last when
  // run() returns). The images are the same bits either way (the filter is a pure
  // function of its frame and its history, and the history is fed in frame order). Why:
  // a GPU renders while the host's cores are idle, so the filter costs the frame rate
  // nothing there; where the host's cores render too, the filter slows them while it runs,
  // and the balancer sees that in their times like any other load. Ignored with several
  // lanes (a bench's balancers take turns on the same devices, and one lane's filter would
  // slow the next lane's frame). Off by default. Call before run().
  void set_denoise_overlap(bool on) { overlap_denoise_ = on; }
  // Which lane renders first in each frame. Off (the default): lane 0, 1, ... in every
  // frame. On: frame f starts at lane (f + offset) mod L and goes round, so every lane
  // renders first, second, ... equally often (a bench gives each repeat block another
  // offset, so that one frame does not put the same lane first in every block); the
  // observer is still handed the frame's results in lane order, after the last lane. Why: the
  // first lane of a frame runs on colder caches, by 1-5% on the real pairs here
  // (docs/benchmarks.md, "Lane order"), which in a fixed order is always the same balancer's loss.
  // Call before run().
  void set_rotate_lanes(bool on, size_t offset = 0) {
    rotate_lanes_ = on;
    rotate_offset_ = offset;
  }

  // Asks run() to return after the frame being rendered; asked between runs, the next
  // run() returns before its first frame. Each request stops one run. Thread-safe (signal
  // handlers should set a flag that an observer or another thread turns into this call).
  void request_stop() { stop_ = true; }

  // Renders frames [first, first + count) on every lane, calling `observer` as described
  // above. Returns the number of frames every lane completed (fewer after request_stop()).
  // Throws DeviceError when every device of a lane has failed.
  int run(int first, int count, FrameObserver& observer);

  size_t lanes() const { return engines_.size(); }
  Engine& engine(size_t lane) { return *engines_.at(lane); }
  // Progress of the frame being rendered in [0, 1], for a progress display; thread-safe.
  double progress() const;
  const FrameViews& views() const { return views_; }

 private:
  std::shared_ptr<FrameResult> free_buffer(size_t lane);
  // Lane `lane`'s rendering of `frame` (its record, images, denoised images and plan).
  std::shared_ptr<FrameResult> render_lane(size_t lane, int frame, FrameInput& input);
  // One frame on every lane (run()'s loop body).
  void run_frame(int frame, FrameObserver& observer);
  Camera camera_at(int frame) const;
  // Lane `lane`'s denoiser on the frame it just rendered into `out` (out.denoised), whose
  // views are `views`; returns its time, ms. `scaled`: the views at the reduced image scale
  // they were rendered at (Engine::scaled_images), filtered at that size and enlarged
  // after (FrameDenoiser::apply_scaled); null: filtered at the output size.
  double denoise_lane(size_t lane, const std::vector<ViewSetup>& views,
                      const std::vector<Framebuffer>* scaled, FrameResult& out);
  // The views the denoiser of the frame lane `lane` just rendered filters at a reduced
  // size, or null (a reprojected frame's views are completed at the output size).
  const std::vector<Framebuffer>* scaled_for_denoise(size_t lane, const FrameInput& input) const;
  // set_denoise_overlap is on and applies to this frame.
  bool overlapping() const {
    return overlap_denoise_ && engines_.size() == 1 && !denoisers_.empty();
  }
  // Starts the denoiser of `out`, just rendered by lane `lane`, beside the next frame.
  void start_overlapped(size_t lane, const FrameInput& input, std::shared_ptr<FrameResult> out);
  // Waits for the overlapped denoiser, if one runs, and hands its frame to `observer`.
  void finish_overlapped(FrameObserver& observer);
  // Takes up the method set_denoise() asked for (between frames, on run()'s thread).
  void take_up_denoise();
  void continue_sequence(int frame, const Camera& camera, FrameInput& input);

  std::vector<Device*> devices_;
  std::vector<std::unique_ptr<Engine>> engines_;
  std::vector<std::vector<std::shared_ptr<FrameResult>>> buffers_;  // per lane
  FrameViews views_;
  CameraPath path_;
  RenderSettings settings_;
  std::function<void(int, RenderSettings&)> schedule_;
  mutable std::mutex camera_mutex_;
  std::optional<Camera> camera_;
  std::atomic<bool> stop_{false};
  std::atomic<size_t> active_lane_{0};
  // The sample sequence progressive frames continue: begun at `frame` (-1: none yet) under
  // `camera` and the settings whose sent values are `settings`; `next` its next sample.
  bool progressive_ = false;
  bool rotate_lanes_ = false;
  size_t rotate_offset_ = 0;
  struct Sequence {
    int frame = -1;
    Camera camera;
    std::vector<std::string> settings;
    uint32_t next = 0;
  } sequence_;
  bool last_full_quality_ = true;  // the frame before was rendered at full quality
  std::atomic<DenoiseMethod> denoise_request_{DenoiseMethod::none};
  DenoiseMethod denoise_ = DenoiseMethod::none;  // of denoisers_
  DenoiseParams denoise_params_;
  std::vector<FrameDenoiser> denoisers_;  // per lane, or none
  bool overlap_denoise_ = false;
  // The frame whose denoiser runs on filter_job_ (set_denoise_overlap), until handed over.
  std::shared_ptr<FrameResult> overlapped_;
  // Last: destroyed first, so a job still running ends before what it uses.
  BackgroundJob filter_job_;
};

}  // namespace multiray
