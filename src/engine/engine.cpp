#include "engine/engine.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/clock.h"
#include "core/error.h"
#include "engine/plan_source.h"
#include "render/foveation_frame.h"

namespace multiray {

void imbalance_of(const std::vector<double>& t, double& imbalance, double& deviation) {
  imbalance = deviation = 0;
  if (t.size() < 2) return;
  double sum = 0, mx = 0;
  for (double x : t) sum += x, mx = std::max(mx, x);
  const double mean = sum / double(t.size());
  if (!(mean > 0)) return;
  imbalance = mx / mean - 1.0;
  for (double x : t) deviation = std::max(deviation, std::abs(x - mean) / mean);
}

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

}  // namespace

Engine::Engine(std::vector<Device*> devices, std::unique_ptr<balance::Balancer> balancer)
    : devices_(std::move(devices)),
      threads_(devices_.size()),
      balancer_(std::move(balancer)),
      alive_(devices_.size(), true) {
  if (devices_.empty()) throw InputError("no devices to render with");
}

FrameRecord Engine::render_frame(int frame, const std::vector<ViewSetup>& views,
                                 const RenderSettings& settings) {
  const size_t n = devices_.size();
  FrameRecord rec;
  rec.frame = frame;
  for (const Perturbation& p : perturbations_)
    if (p.frame == frame && p.device >= 0 && size_t(p.device) < n)
      devices_[size_t(p.device)]->set_emulated_speed(p.speed);

  balance::FrameShape shape;
  shape.width = views.at(0).width;
  shape.height = views.at(0).height;
  shape.views = int(views.size());
  shape.pixel_weight = pixel_weights(views, settings);
  images_.resize(views.size());
  for (auto& img : images_)
    if (img.width != shape.width || img.height != shape.height)
      img = Framebuffer(shape.width, shape.height);

  Stopwatch clock;
  last_plan_ = balancer_->plan(shape, frame);
  rec.plan_ms = clock.elapsed_ms();
  handed_out_ = 0;
  frame_pixels_ = shape.pixels();
  PlanWorkSource source(last_plan_, shape, &handed_out_);
  FrameJob job{views, settings, &images_};

  // Every live device renders on its own thread; the device measures its own time.
  std::vector<DeviceReport> reports(n);
  clock.restart();
  std::vector<std::function<void()>> jobs(n);
  for (size_t i = 0; i < n; ++i)
    if (alive_[i]) jobs[i] = [&, i] { reports[i] = devices_[i]->render(job, source, int(i)); };
  threads_.run(jobs);
  rec.frame_ms = clock.elapsed_ms();

  // Gather: devices wrote their pixels in place; what is left is work a failed device
  // did not finish, which the first live device renders now.
  clock.restart();
  for (size_t i = 0; i < n; ++i) {
    if (!alive_[i] || !reports[i].failed) continue;
    alive_[i] = false;
    balancer_->drop_device(int(i));
    rec.messages.push_back("device " + std::to_string(i) + " (" + devices_[i]->info().name +
                           ") failed and was dropped: " + reports[i].error);
    std::vector<bool> done(source.items().size(), false);
    for (const UnitReport& u : reports[i].units) done[u.unit.id] = true;
    std::vector<WorkUnit> redo;
    for (uint32_t id = 0; id < source.items().size(); ++id)
      if (source.taken_by(id) == int(i) && !done[id])
        redo.push_back(to_unit(source.items()[id], id));
    for (uint32_t id : source.take_remaining(int(i)))
      redo.push_back(to_unit(source.items()[id], id));
    const auto helper = std::find(alive_.begin(), alive_.end(), true);
    if (helper == alive_.end()) throw DeviceError("every device has failed: " + reports[i].error);
    const size_t h = size_t(helper - alive_.begin());
    ListWorkSource list(redo);
    DeviceReport extra;
    std::vector<std::function<void()>> redo_job(n);
    redo_job[h] = [&] { extra = devices_[h]->render(job, list, int(h)); };
    threads_.run(redo_job);
    DeviceReport& r = reports[h];
    r.units.insert(r.units.end(), extra.units.begin(), extra.units.end());
    r.samples += extra.samples, r.pixels += extra.pixels, r.rays += extra.rays;
    r.busy_ms += extra.busy_ms, r.wall_ms += extra.wall_ms;
  }
  rec.gather_ms = clock.elapsed_ms();
  rec.stolen = source.stolen();

  // Stats for the record and for the balancer.
  balance::FrameStats stats;
  stats.frame = frame;
  stats.shape = shape;
  stats.devices.resize(n);
  uint64_t total_samples = 0;
  for (const auto& r : reports) total_samples += r.samples;
  std::vector<double> live_times;
  rec.devices.resize(n);
  rendered_.assign(n, {});
  for (size_t i = 0; i < n; ++i) {
    const DeviceReport& r = reports[i];
    DeviceFrameRecord& d = rec.devices[i];
    d.alive = alive_[i];
    d.time_ms = r.wall_ms, d.busy_ms = r.busy_ms;
    d.samples = r.samples, d.pixels = r.pixels, d.rays = r.rays;
    d.units = int(r.units.size());
    d.work_share = total_samples ? double(r.samples) / double(total_samples) : 0.0;
    d.planned_share = i < last_plan_.ratios.size() ? last_plan_.ratios[i] : 0.0;
    if (alive_[i]) live_times.push_back(r.wall_ms);
    balance::DeviceFrameStats& s = stats.devices[i];
    s.alive = alive_[i];
    s.time_ms = r.wall_ms, s.busy_ms = r.busy_ms;
    s.samples = double(r.samples), s.pixels = double(r.pixels);
    for (const UnitReport& u : r.units) {
      s.items.push_back({source.items()[u.unit.id], u.time_ms, double(u.samples)});
      rendered_[i].push_back(source.items()[u.unit.id]);
    }
  }
  imbalance_of(live_times, rec.imbalance, rec.deviation);
  clock.restart();
  balancer_->update(stats);
  rec.update_ms = clock.elapsed_ms();
  return rec;
}

}  // namespace multiray
