#include "engine/engine.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/clock.h"
#include "core/error.h"
#include "core/resample.h"
#include "device/work_list.h"
#include "engine/dispatch_source.h"
#include "render/foveation_frame.h"

namespace multiray {

namespace {

// Irregular sampling: the samples of every pixel of every view (views·height·width values,
// as FrameShape::pixel_weight), so balancers that split by work see where the work is.
// Adaptive views give their sample map, foveated views the samples positioned in each
// pixel, the others settings.spp everywhere. Empty when no view samples irregularly.
std::vector<float> pixel_weights(const std::vector<ViewSetup>& views,
                                 const RenderSettings& settings) {
  std::vector<float> w;
  bool irregular = false;
  for (const ViewSetup& v : views) irregular |= v.spp_map || v.foveation;
  if (!irregular) return w;
  for (const ViewSetup& v : views) {
    const size_t n = size_t(v.width) * size_t(v.height);
    if (v.foveation)
      w.insert(w.end(), v.foveation->pixel_samples.begin(), v.foveation->pixel_samples.end());
    else if (v.spp_map)
      for (uint8_t spp : *v.spp_map) w.push_back(float(spp));
    else
      w.insert(w.end(), n, float(settings.spp));
  }
  return w;
}

// One framebuffer per view of width x height (reused when the size is right), with an
// alpha channel when the settings have a shadow catcher (render/shadow_catcher.h) and
// feature buffers when they ask for them (none otherwise: nothing allocated).
void size_images(std::vector<Framebuffer>& images, size_t views, int width, int height,
                 const RenderSettings& settings) {
  images.resize(views);
  for (auto& img : images) {
    if (img.width != width || img.height != height) img = Framebuffer(width, height);
    img.alpha.resize(settings.catcher_axis >= 0 ? img.pixels.size() : 0);
    if (settings.feature_buffers)
      img.features.resize(width, height);
    else if (!img.features.empty())
      img.features.clear();
  }
}

}  // namespace

Engine::Engine(std::vector<Device*> devices, std::unique_ptr<balance::Balancer> balancer)
    : devices_(std::move(devices)),
      threads_(devices_.size()),
      balancer_(std::move(balancer)),
      alive_(devices_.size(), true) {
  if (devices_.empty()) throw InputError("no devices to render with");
}

void Engine::set_balancer(std::unique_ptr<balance::Balancer> balancer) {
  if (!balancer) throw InputError("no balancer");
  balancer_ = std::move(balancer);
  for (size_t i = 0; i < alive_.size(); ++i)
    if (!alive_[i]) balancer_->drop_device(int(i));
}

void Engine::apply_perturbations(int frame) {
  for (const Perturbation& p : perturbations_)
    if (p.frame == frame && p.device >= 0 && size_t(p.device) < devices_.size())
      devices_[size_t(p.device)]->set_emulated_speed(p.speed);
}

FrameRecord Engine::render_frame(int frame, const std::vector<ViewSetup>& views,
                                 const RenderSettings& settings,
                                 std::vector<Framebuffer>& images) {
  const Stopwatch wall;
  FrameRecord rec;
  rec.frame = frame;
  apply_perturbations(frame);
  FrameAdvice advice;
  if (advisor_) {
    Stopwatch clock;
    advice = advisor_->advise(frame, views, settings);
    advice.advise_ms = rec.advise_ms = clock.elapsed_ms();
    rec.predicted_ms = advice.predicted_ms;
  }
  render_pass(frame, views, settings, advice, images, rec);
  if (advisor_)
    if (std::optional<FrameAdvice> second = advisor_->second_pass(advice, rec)) {
      const FrameRecord first = std::move(rec);
      advice = std::move(*second);
      rec = FrameRecord{};
      rec.frame = frame;
      render_pass(frame, views, settings, advice, images, rec);
      rec.first_pass_ms = first.frame_ms;
      rec.frame_ms += first.frame_ms, rec.plan_ms += first.plan_ms;
      rec.gather_ms += first.gather_ms, rec.stolen += first.stolen;
      rec.advise_ms = first.advise_ms;
      rec.predicted_ms = advice.predicted_ms > 0 ? first.frame_ms + advice.predicted_ms : 0;
      rec.messages.insert(rec.messages.begin(), first.messages.begin(), first.messages.end());
      rec.notes.insert(rec.notes.begin(), first.notes.begin(), first.notes.end());
    }

  // The balancer and the advisor learn from the pass that became the frame.
  Stopwatch clock;
  balancer_->update(stats_);
  rec.update_ms = clock.elapsed_ms();
  if (advisor_) {
    clock.restart();
    advisor_->measured(advice, rec, stats_);
    rec.learn_ms = clock.elapsed_ms();
    advisor_->annotate(rec);
  }
  rec.wall_ms = wall.elapsed_ms();
  return rec;
}

void Engine::render_pass(int frame, const std::vector<ViewSetup>& views,
                         const RenderSettings& settings, const FrameAdvice& advice,
                         std::vector<Framebuffer>& images, FrameRecord& rec) {
  const balance::FrameShape shape = plan_pass(frame, views, settings, advice, rec);
  size_images(images, views.size(), shape.width, shape.height, settings);

  // The plan's quality: smaller views (rendered into scaled_images_, upsampled after with
  // their feature buffers, core/resample.h) and a longer ray step. Sample maps are per
  // output pixel and do not scale.
  const double scale = last_plan_.quality.image_scale;
  const bool scaled = scale != 1.0;
  for (const ViewSetup& v : views)
    if (scaled && (v.spp_map || v.foveation))
      throw InputError("a reduced image scale does not work with adaptive or foveated sampling");
  const balance::FrameShape rendered = balance::scaled_shape(shape, scale);
  last_scaled_ = scaled;
  FrameJob job{views, settings, scaled ? &scaled_images_ : &images};
  job.settings.step_scale = float(settings.step_scale * last_plan_.quality.step_scale);
  for (ViewSetup& v : job.views) v.width = rendered.width, v.height = rendered.height;
  if (scaled) size_images(scaled_images_, views.size(), rendered.width, rendered.height, settings);

  handed_out_ = 0;
  frame_pixels_ = rendered.pixels();
  DispatchSource source(last_plan_, rendered, &handed_out_);
  Stopwatch clock;
  std::vector<DeviceReport> reports = run_devices(job, source);
  rec.frame_ms = clock.elapsed_ms();

  clock.restart();
  recover_failures(job, source, reports, rec);
  if (scaled)
    for (size_t v = 0; v < images.size(); ++v) upscale_bilinear(scaled_images_[v], images[v]);
  rec.gather_ms = clock.elapsed_ms();
  rec.stolen = source.dispatcher().stolen();

  stats_ = balance::FrameStats{};
  stats_.frame = frame;
  stats_.shape = rendered;
  record(reports, rec);
}

balance::FrameShape Engine::plan_pass(int frame, const std::vector<ViewSetup>& views,
                                      const RenderSettings& settings, const FrameAdvice& advice,
                                      FrameRecord& rec) {
  balance::FrameShape shape;
  shape.width = views.at(0).width;
  shape.height = views.at(0).height;
  shape.views = int(views.size());
  shape.pixel_weight = pixel_weights(views, settings);
  // Sample maps say where samples are; predictions only add where there are none.
  if (shape.pixel_weight.empty() && int64_t(advice.pixel_work.size()) == shape.pixels())
    shape.pixel_weight = advice.pixel_work;
  shape.device_cost = advice.device_cost;
  Stopwatch clock;
  last_plan_ = balancer_->plan(balance::scaled_shape(shape, advice.quality.image_scale), frame);
  rec.plan_ms = clock.elapsed_ms();
  note_participation(rec);
  if (advisor_) {
    if (last_plan_.quality.image_scale != 1 || last_plan_.quality.step_scale != 1)
      throw InputError("balancer " + balancer_->name() +
                       " sets its own quality and cannot run with frame-time targeting");
    last_plan_.quality = advice.quality;
  }
  rec.quality = last_plan_.quality;
  return shape;
}

std::vector<DeviceReport> Engine::run_devices(const FrameJob& job, WorkSource& source) {
  // Every live device renders on its own thread; the device measures its own time.
  const size_t n = devices_.size();
  std::vector<DeviceReport> reports(n);
  std::vector<std::function<void()>> jobs(n);
  // A device the plan leaves out is not started: no upload, no launch, no wait.
  for (size_t i = 0; i < n; ++i)
    if (alive_[i] && !last_plan_.rests(i))
      jobs[i] = [&, i] { reports[i] = devices_[i]->render(job, source, int(i)); };
  threads_.run(jobs);
  return reports;
}

void Engine::note_participation(FrameRecord& rec) {
  // One line when a device is left out or comes back, not every frame.
  resting_.resize(devices_.size(), false);
  for (size_t i = 0; i < devices_.size(); ++i) {
    const bool rests = last_plan_.rests(i);
    if (rests == resting_[i]) continue;
    resting_[i] = rests;
    const std::string who = devices_[i]->info().spec;
    const std::string why =
        i < last_plan_.rest_reason.size() ? last_plan_.rest_reason[i] : std::string();
    rec.notes.push_back(rests ? who + " left out" + (why.empty() ? "" : ": " + why)
                              : who + " takes part again");
  }
}

void Engine::recover_failures(const FrameJob& job, DispatchSource& source,
                              std::vector<DeviceReport>& reports, FrameRecord& rec) {
  balance::Dispatcher& dispatch = source.dispatcher();
  for (size_t i = 0; i < devices_.size(); ++i) {
    if (!alive_[i] || !reports[i].failed) continue;
    alive_[i] = false;
    balancer_->drop_device(int(i));
    rec.messages.push_back("device " + std::to_string(i) + " (" + devices_[i]->info().name +
                           ") failed and was dropped, its work re-assigned: " + reports[i].error);
    // What it started but did not report, and what was still waiting in its list.
    std::vector<bool> done(dispatch.items().size(), false);
    for (const ItemReport& r : reports[i].items) done[r.id] = true;
    std::vector<uint32_t> redo;
    for (uint32_t id = 0; id < dispatch.items().size(); ++id)
      if (dispatch.taken_by(id) == int(i) && !done[id]) redo.push_back(id);
    for (uint32_t id : dispatch.take_remaining(int(i))) redo.push_back(id);

    // A helper is a device that did not fail this frame too (all ranks go silent at once
    // when the master's own link is cut: each is named, not only the last one seen). One
    // that fails while re-rendering is dropped in turn and what it left goes on to the
    // next: a second fault in one frame lost those items without a word before.
    std::vector<uint32_t> left = std::move(redo);
    for (;;) {
      size_t h = 0;
      while (h < devices_.size() && !(alive_[h] && !reports[h].failed)) ++h;
      if (h == devices_.size()) {
        std::string why;
        for (const DeviceReport& r : reports)
          if (r.failed) why += (why.empty() ? "" : "; ") + r.error;
        throw DeviceError("every device has failed: " + why);
      }
      std::vector<WorkItem> items;
      for (uint32_t id : left) items.push_back(dispatch.items()[id]);
      ListWorkSource list(items, left);
      DeviceReport extra;
      std::vector<std::function<void()>> redo_job(devices_.size());
      redo_job[h] = [&] { extra = devices_[h]->render(job, list, int(h)); };
      threads_.run(redo_job);
      DeviceReport& r = reports[h];
      r.items.insert(r.items.end(), extra.items.begin(), extra.items.end());
      r.samples += extra.samples, r.pixels += extra.pixels, r.rays += extra.rays;
      r.busy_ms += extra.busy_ms, r.time_ms += extra.time_ms;
      r.stolen_ms += extra.stolen_ms;
      if (!extra.failed) break;
      std::vector<bool> redone(dispatch.items().size(), false);
      for (const ItemReport& it : extra.items) redone[it.id] = true;
      left.erase(std::remove_if(left.begin(), left.end(), [&](uint32_t id) { return redone[id]; }),
                 left.end());
      alive_[h] = false;
      balancer_->drop_device(int(h));
      r.failed = true;
      r.error = extra.error;
      rec.messages.push_back("device " + std::to_string(h) + " (" + devices_[h]->info().name +
                             ") failed while re-rendering the items of device " +
                             std::to_string(i) +
                             " and was dropped, its work re-assigned: " + extra.error);
    }
  }
}

void Engine::record(std::vector<DeviceReport>& reports, FrameRecord& rec) {
  const size_t n = devices_.size();
  uint64_t total_samples = 0;
  for (const auto& r : reports) total_samples += r.samples;
  std::vector<double> live_times;
  stats_.devices.resize(n);
  rendered_.assign(n, {});
  for (size_t i = 0; i < n; ++i) {
    DeviceReport& r = reports[i];
    r.alive = alive_[i];
    r.rested = alive_[i] && last_plan_.rests(i);
    r.work_share = total_samples ? double(r.samples) / double(total_samples) : 0.0;
    r.planned_share = i < last_plan_.ratios.size() ? last_plan_.ratios[i] : 0.0;
    if (alive_[i] && !r.rested) live_times.push_back(r.time_ms);
    balance::DeviceFrameStats& s = stats_.devices[i];
    s.alive = alive_[i];
    s.rested = r.rested;
    s.time_ms = r.time_ms, s.busy_ms = r.busy_ms;
    s.samples = double(r.samples), s.pixels = double(r.pixels);
    s.items = r.items;
    for (const ItemReport& it : r.items) rendered_[i].push_back(it.item);
  }
  rec.models = last_plan_.models;
  rec.imbalance = balance::imbalance(live_times);
  rec.deviation = balance::deviation(live_times);
  rec.devices = std::move(reports);
}

}  // namespace multiray
