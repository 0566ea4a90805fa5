#include "engine/bench_harness.h"

#include <limits>

#include <algorithm>
#include <thread>

#include "core/error.h"
#include "device/work_list.h"
#include "render/volume_raycaster.h"

namespace multiray {

std::vector<int> spread_frames(int first, int frames, int count) {
  std::vector<int> out;
  const int span = frames - first;
  count = std::min(count, span);
  for (int k = 0; k < count; ++k) out.push_back(first + int(int64_t(k) * span / count));
  return out;
}

namespace {

// Emulated speeds as the perturbations set them at `frame`.
std::vector<double> speeds_at(const std::vector<Perturbation>& perturbations,
                              std::vector<double> speeds, int frame) {
  for (const Perturbation& p : perturbations)
    if (p.frame <= frame) speeds[size_t(p.device)] = p.speed;
  return speeds;
}

// Each device renders all of `in` alone at the frame's emulated speeds, on a thread of its
// own (as in the engine, so pinning and quotas apply to that thread only). Leaves the
// devices at those speeds.
IdealSample measure_ideal(const std::vector<Device*>& devices, const std::vector<double>& speeds,
                          const FrameInput& in, const RenderSettings& settings, int frame) {
  const int w = in.views.at(0).width, h = in.views.at(0).height;
  std::vector<Framebuffer> out(in.views.size(), Framebuffer(w, h));
  if (settings.feature_buffers)  // recorded as in the frame: the same work
    for (Framebuffer& f : out) f.features.resize(w, h);
  const FrameJob job{in.views, settings, &out};
  IdealSample sample;
  sample.frame = frame;
  double inv = 0;
  for (size_t i = 0; i < devices.size(); ++i) {
    devices[i]->set_emulated_speed(speeds[i]);
    std::vector<WorkItem> whole;
    for (int v = 0; v < int(in.views.size()); ++v) whole.push_back(WorkItem{Rect{0, 0, w, h}, v});
    ListWorkSource source(whole);
    DeviceReport r;
    std::thread([&] { r = devices[i]->render(job, source, int(i)); }).join();
    if (r.failed) throw DeviceError("device " + std::to_string(i) + " failed: " + r.error);
    inv += 1.0 / std::max(r.time_ms, 1e-6);
    sample.device_alone_ms.push_back(r.time_ms);
  }
  sample.ideal_ms = 1.0 / inv;
  return sample;
}

// View 0 of `in` rendered by `device` alone with `settings` (the frame's own).
Framebuffer render_reference(Device& device, const FrameInput& in,
                             const RenderSettings& settings) {
  const int w = in.views.at(0).width, h = in.views.at(0).height;
  std::vector<Framebuffer> out(1, Framebuffer(w, h));
  if (settings.feature_buffers) out[0].features.resize(w, h);
  const std::vector<ViewSetup> view0(1, in.views.at(0));
  const FrameJob job{view0, settings, &out};
  ListWorkSource source({WorkItem{Rect{0, 0, w, h}, 0}});
  DeviceReport r;
  std::thread([&] { r = device.render(job, source, 0); }).join();
  if (r.failed) throw DeviceError("device 0 failed on the reference: " + r.error);
  return std::move(out[0]);
}

class BenchObserver : public FrameObserver {
 public:
  BenchObserver(const Session& session, const std::vector<Device*>& devices,
                const std::vector<double>& speeds, const std::vector<Perturbation>& perturbations,
                const RenderSettings& settings, const BenchConfig& config,
                const std::function<void(int)>& on_frame, BenchResult& result)
      : session_(session),
        devices_(devices),
        speeds_(speeds),
        perturbations_(perturbations),
        settings_(settings),
        config_(config),
        on_frame_(on_frame),
        result_(result) {}

  void before_frame(int frame, const FrameInput& in) override {
    if (on_frame_) on_frame_(frame);
    result_.sampling_ms.push_back(in.sampling_ms);
    if (in.reprojection) result_.hole_fraction.push_back(in.reprojection->hole_fraction());
    if (std::find(result_.sampled.begin(), result_.sampled.end(), frame) != result_.sampled.end())
      result_.ideal.push_back(measure_ideal(devices_, speeds_at(perturbations_, speeds_, frame),
                                            in, settings_, frame));
    fine_.reset();
    const RenderSettings& now = session_.settings();
    if (config_.reference_step > 0 && now.volume_style && !devices_.empty()) {
      if (fine_style_of_ != now.volume_style) {  // once per transfer function
        auto fine = std::make_shared<VolumeStyle>(*now.volume_style);
        fine->step = config_.reference_step;
        fine_style_ = fine, fine_style_of_ = now.volume_style;
      }
      RenderSettings fine_settings = now;
      fine_settings.volume_style = fine_style_;
      fine_settings.step_scale = 1;
      fine_ = std::make_shared<Framebuffer>(render_reference(*devices_[0], in, fine_settings));
    }
  }

  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    BenchLane& lane = result_.lanes[r->lane];
    // Kept for the summary, the JSON and the plots, none of which reads the per-item
    // reports (the trace has its own, lane.stats): they are dropped, so that a long bench
    // keeps about 1 KB a frame and lane instead of tens of KB with a queue's tiles.
    lane.records.push_back(r->record);
    for (DeviceReport& d : lane.records.back().devices) std::vector<ItemReport>().swap(d.items);
    uint64_t hash = 0xcbf29ce484222325ull;
    for (const Framebuffer& img : r->images) hash = image_hash(img, hash);
    lane.image_hashes.push_back(hash);
    // Lanes at the same quality must agree bit for bit; frame-time targeting renders
    // lanes at different qualities, which are not compared.
    if (r->lane == 0) frame_quality_.clear();
    for (const auto& [q, h] : frame_quality_)
      if (q.image_scale == r->record.quality.image_scale &&
          q.step_scale == r->record.quality.step_scale) {
        if (h != hash) result_.mismatched_frames[r->lane].push_back(r->frame);
        break;
      }
    frame_quality_.emplace_back(r->record.quality, hash);
    const balance::Quality full;
    if (fine_)
      lane.error_vs_reference.push_back(image_error(r->images.at(0), *fine_));
    else if (r->lane == 0)
      reference_ = r->record.quality.image_scale == full.image_scale &&
                           r->record.quality.step_scale == full.step_scale
                       ? r
                       : nullptr;
    else if (reference_ && reference_->frame == r->frame)
      lane.error_vs_reference.push_back(
          hash == result_.lanes[0].image_hashes.back()
              ? ImageError{0, std::numeric_limits<double>::infinity(), 1}
              : image_error(r->images.at(0), reference_->images.at(0)));
    if (r->frame == config_.partition_frame) {
      lane.partition = r->rendered;
      if (!r->images.empty()) lane.partition_image = r->images[0];
    }
    if (config_.keep_stats) lane.stats.push_back(r->stats);
  }

 private:
  const Session& session_;
  const std::vector<Device*>& devices_;
  const std::vector<double>& speeds_;
  const std::vector<Perturbation>& perturbations_;
  const RenderSettings& settings_;
  const BenchConfig& config_;
  // This frame's lanes so far: the quality each rendered at and its image hash.
  std::vector<std::pair<balance::Quality, uint64_t>> frame_quality_;
  std::shared_ptr<const FrameResult> reference_;  // lane 0's frame, if at full quality
  std::shared_ptr<const Framebuffer> fine_;       // this frame at reference_step
  std::shared_ptr<const VolumeStyle> fine_style_, fine_style_of_;  // and the style it used
  const std::function<void(int)>& on_frame_;
  BenchResult& result_;
};

}  // namespace

BenchResult run_bench(Session& session, const std::vector<Device*>& devices,
                      const std::vector<double>& speeds,
                      const std::vector<Perturbation>& perturbations,
                      const RenderSettings& settings, const BenchConfig& config,
                      const std::function<void(int)>& on_frame) {
  BenchResult result;
  result.sampled = spread_frames(config.warmup, config.frames, config.ideal_frames);
  result.lanes.resize(session.lanes());
  result.mismatched_frames.resize(session.lanes());
  for (size_t k = 0; k < session.lanes(); ++k)
    result.lanes[k].spec = session.engine(k).balancer().spec();
  BenchObserver observer(session, devices, speeds, perturbations, settings, config, on_frame,
                         result);
  session.run(0, config.frames, observer);
  return result;
}

}  // namespace multiray
