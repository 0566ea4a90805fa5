// One frame at a time: plan -> all devices render concurrently -> gather -> stats ->
// balancer update. One Engine per (device set, balancer); frames are rendered in order.
// The frame loop around it (views per frame, observers, several balancers) is Session.
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <vector>

#include "balance/balancer.h"
#include "core/image.h"
#include "device/device.h"
#include "engine/device_threads.h"
#include "engine/frame_advisor.h"
#include "engine/frame_record.h"

namespace multiray {

// --perturb FRAME:DEVICE:SPEED: from `frame` on, device `device` runs at emulated `speed`.
struct Perturbation {
  int frame = 0;
  int device = 0;
  double speed = 1.0;
};

class DispatchSource;

class Engine {
 public:
  Engine(std::vector<Device*> devices, std::unique_ptr<balance::Balancer> balancer);

  // Renders all `views` of `frame` (same size each) into `images` (resized to one
  // output-size image per view) and returns the measurements. Applies the plan's quality:
  // at image_scale < 1 the views are rendered smaller and upscaled bilinearly, feature
  // buffers too (core/resample.h: output-size buffers that describe the enlarged beauty);
  // the settings' step_scale is multiplied by the plan's. Throws DeviceError
  // when every device has failed, InputError for a reduced image scale with irregular sampling.
  // With an advisor that asks for a second pass (two-pass targeting) the frame is rendered twice
  // and the record covers both (FrameRecord::first_pass_ms).
  FrameRecord render_frame(int frame, const std::vector<ViewSetup>& views,
                           const RenderSettings& settings, std::vector<Framebuffer>& images);
  // The same into images() (tests, simple callers).
  FrameRecord render_frame(int frame, const std::vector<ViewSetup>& views,
                           const RenderSettings& settings) {
    return render_frame(frame, views, settings, images_);
  }

  const std::vector<Framebuffer>& images() const { return images_; }
  // The last frame's views as the devices rendered them, before they were enlarged to the
  // output size (with their feature buffers: the session's denoiser filters these), or
  // null when it was rendered at the output size (image_scale 1).
  const std::vector<Framebuffer>* scaled_images() const {
    return last_scaled_ ? &scaled_images_ : nullptr;
  }
  const balance::Plan& last_plan() const { return last_plan_; }
  // The items each device actually rendered in the last frame (after pulls and steals).
  const std::vector<std::vector<balance::WorkItem>>& last_rendered() const { return rendered_; }
  // What the balancer was told about the last frame (per-item times included).
  const balance::FrameStats& last_stats() const { return stats_; }
  balance::Balancer& balancer() { return *balancer_; }
  // Replaces the balancer for the following frames (e.g. switched from a live viewer);
  // devices that died stay dropped. Call between frames only.
  void set_balancer(std::unique_ptr<balance::Balancer> balancer);
  void set_perturbations(std::vector<Perturbation> p) { perturbations_ = std::move(p); }
  // Predictions and frame-time targeting for the following frames (frame_advisor.h), or
  // null for none. The balancer then plans each frame at the advised image scale and must
  // leave Plan::quality at full quality (render_frame throws InputError otherwise).
  void set_advisor(std::unique_ptr<FrameAdvisor> advisor) { advisor_ = std::move(advisor); }
  FrameAdvisor* advisor() { return advisor_.get(); }
  bool alive(int device) const { return alive_[size_t(device)]; }
  size_t device_count() const { return devices_.size(); }
  // Fraction of the current frame's pixels handed to devices so far, in [0, 1]; safe to
  // call from another thread while render_frame() runs (for progress display).
  double progress() const {
    const int64_t total = frame_pixels_.load();
    return total > 0 ? std::min(1.0, double(handed_out_.load()) / double(total)) : 0.0;
  }

 private:
  void apply_perturbations(int frame);
  // One pass over `views`: plan (plan_pass), render, recover failures, upsample into
  // `images`; fills rec's times and devices and stats_. The caller updates the balancer.
  void render_pass(int frame, const std::vector<ViewSetup>& views, const RenderSettings& settings,
                   const FrameAdvice& advice, std::vector<Framebuffer>& images, FrameRecord& rec);
  // The plan of a pass (into last_plan_): the balancer's, over the advisor's predictions
  // and at its quality. Returns the output-size shape the plan was made for (unscaled).
  balance::FrameShape plan_pass(int frame, const std::vector<ViewSetup>& views,
                                const RenderSettings& settings, const FrameAdvice& advice,
                                FrameRecord& rec);
  std::vector<DeviceReport> run_devices(const FrameJob& job, WorkSource& source);
  // Re-renders what failed devices left, on the first live device; drops the failed ones.
  // Adds a message to `rec` for each device the new plan leaves out or takes back.
  void note_participation(FrameRecord& rec);
  void recover_failures(const FrameJob& job, DispatchSource& source,
                        std::vector<DeviceReport>& reports, FrameRecord& rec);
  // Fills rec.devices, rendered_ and stats_ from the reports.
  void record(std::vector<DeviceReport>& reports, FrameRecord& rec);

  std::vector<Device*> devices_;
  DeviceThreads threads_;
  std::unique_ptr<balance::Balancer> balancer_;
  std::unique_ptr<FrameAdvisor> advisor_;
  std::vector<Framebuffer> images_, scaled_images_;
  bool last_scaled_ = false;  // the last pass was rendered into scaled_images_
  std::vector<bool> alive_;
  std::vector<bool> resting_;  // left out by the last plan (for note_participation)
  std::vector<Perturbation> perturbations_;
  balance::Plan last_plan_;
  balance::FrameStats stats_;
  std::vector<std::vector<balance::WorkItem>> rendered_;
  std::atomic<int64_t> handed_out_{0}, frame_pixels_{0};
};

}  // namespace multiray
