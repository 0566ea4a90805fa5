// The frame loop: plan -> all devices render concurrently -> gather -> stats -> balancer
// update. One Engine per (scene, device set, balancer); frames are rendered in order.
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <vector>

#include "balance/balancer.h"
#include "core/image.h"
#include "device/device.h"
#include "engine/device_threads.h"
#include "engine/frame_record.h"

namespace multiray {

// --perturb FRAME:DEVICE:SPEED: from `frame` on, device `device` runs at emulated `speed`.
struct Perturbation {
  int frame = 0;
  int device = 0;
  double speed = 1.0;
};

class Engine {
 public:
  Engine(std::vector<Device*> devices, std::unique_ptr<balance::Balancer> balancer);

  // Renders all `views` of `frame` (same size each) and returns the measurements. The
  // images are in images() afterwards. Throws DeviceError when every device has failed.
  FrameRecord render_frame(int frame, const std::vector<ViewSetup>& views,
                           const RenderSettings& settings);

  const std::vector<Framebuffer>& images() const { return images_; }
  const balance::Plan& last_plan() const { return last_plan_; }
  // The items each device actually rendered in the last frame (after pulls and steals).
  const std::vector<std::vector<balance::WorkItem>>& last_rendered() const { return rendered_; }
  balance::Balancer& balancer() { return *balancer_; }
  void set_perturbations(std::vector<Perturbation> p) { perturbations_ = std::move(p); }
  bool alive(int device) const { return alive_[size_t(device)]; }
  // Fraction of the current frame's pixels handed to devices so far, in [0, 1]; safe to
  // call from another thread while render_frame() runs (for progress display).
  double progress() const {
    const int64_t total = frame_pixels_.load();
    return total > 0 ? std::min(1.0, double(handed_out_.load()) / double(total)) : 0.0;
  }

 private:
  std::vector<Device*> devices_;
  DeviceThreads threads_;
  std::unique_ptr<balance::Balancer> balancer_;
  std::vector<Framebuffer> images_;
  std::vector<bool> alive_;
  std::vector<Perturbation> perturbations_;
  balance::Plan last_plan_;
  std::vector<std::vector<balance::WorkItem>> rendered_;
  std::atomic<int64_t> handed_out_{0}, frame_pixels_{0};
};

}  // namespace multiray
