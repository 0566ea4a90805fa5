#include "engine/volume_advisor.h"

#include <algorithm>
#include <cmath>

#include "core/clock.h"
#include "render/volume_prepass.h"

namespace multiray {

namespace {
// Work that the step does not change, in samples' worth: a ray's set-up and clipping, and
// each block its walk visits. Our addition to the paper's model (whose cost is samples
// only): without it, at coarse steps the prediction falls far below the measured time and
// frame-time targeting keeps coarsening to no effect (aneurism, CPU: a 64x coarser step
// still took 6% of the full-step time).
constexpr double kRaySamples = 1.0, kBlockSamples = 0.5;

}  // namespace

double shaded_share(double weighted, double marched) {
  if (!(marched > 0)) return 0;
  // weighted / marched = s + (1 - s) / 7 for a share s of shaded samples.
  return std::clamp((weighted / marched - 1.0 / 7) * 7.0 / 6.0, 0.0, 1.0);
}

VolumeAdvisor::VolumeAdvisor(const VolumeScene& vs, int device_count,
                             const VolumeAdvisorConfig& config)
    : vs_(vs),
      config_(config),
      targeting_(config.targeting),
      models_(),
      alive_(size_t(std::max(device_count, 0)), true),
      predicted_sigma_(size_t(std::max(device_count, 0)), 0.0),
      measured_sigma_(size_t(std::max(device_count, 0)), 0.0) {
  for (int i = 0; i < device_count; ++i) models_.emplace_back(config.cost_model);
}

CostFeatures VolumeAdvisor::features(double step_scale) const {
  const ViewSetup& view = view_;
  const Camera& c = view.camera;
  const Vec3 d = normalize(c.target - c.eye);
  const double voxel = vs_.volume.voxel_length();
  const double distance = length(c.eye);  // the volume is centred on the origin
  const double pixel =
      distance * 2 * std::tan(0.5 * c.fov_y_deg * kPi / 180) / std::max(view.height, 1);
  return {std::atan2(double(d.x), double(d.z)),
          std::asin(std::clamp(double(d.y), -1.0, 1.0)),
          pixel / voxel,
          style_->step * step_scale,
          prepass_ms_,
          max_depth_ / voxel,
          shaded_share_};
}

double VolumeAdvisor::predict_ms(double c) const {
  const balance::Quality q = balance::quality_of(c, config_.targeting.space);
  const CostFeatures x = features(q.step_scale);
  double rate = 0;  // samples per ms of all live devices together
  for (size_t i = 0; i < models_.size(); ++i) {
    if (!alive_[i]) continue;
    const double sigma = models_[i].predict(x);
    if (!(sigma > 0)) return NAN;
    rate += 1 / sigma;
  }
  const double samples =
      q.image_scale * q.image_scale * (full_samples_ / q.step_scale + fixed_samples_);
  return rate > 0 ? samples / rate : NAN;
}

FrameAdvice VolumeAdvisor::advise(int, const std::vector<ViewSetup>& views,
                                  const RenderSettings& settings) {
  FrameAdvice advice;
  if (!settings.volume_style || views.empty()) return advice;
  style_ = settings.volume_style;
  view_ = views.front();
  // Pre-pass: the samples every output pixel takes at the full-quality step, each counted
  // by its fetches (a shaded sample 1, a transparent one 1/7; volume_prepass.h), and the
  // work the step does not change.
  Stopwatch clock;
  const double step = style_->step * vs_.volume.voxel_length() * settings.step_scale;
  samples_.clear(), fixed_.clear();
  full_samples_ = fixed_samples_ = 0;
  max_depth_ = 0;
  double weighted = 0, marched = 0;  // world units over all coarse pixels
  for (const ViewSetup& v : views) {
    const VolumePrepass p = run_prepass(vs_, *style_, v, config_.prepass_stride, settings.seed);
    max_depth_ = std::max(max_depth_, p.max_depth);
    for (size_t c = 0; c < p.marched.size(); ++c)
      weighted += double(p.weighted[c]), marched += double(p.marched[c]);
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x) {
        const size_t c = size_t(y / p.stride) * size_t(p.width) + size_t(x / p.stride);
        samples_.push_back(float(double(p.weighted[c]) / step));
        fixed_.push_back(float(kRaySamples + kBlockSamples * double(p.blocks[c])));
        full_samples_ += samples_.back(), fixed_samples_ += fixed_.back();
      }
  }
  shaded_share_ = shaded_share(weighted, marched);
  timings_.prepass_ms = prepass_ms_ = clock.elapsed_ms();

  clock.restart();
  const double c = targeting_.next([&](double cost) { return predict_ms(cost); });
  advice_at(c, advice);
  timings_.predict_ms = clock.elapsed_ms();
  return advice;
}

void VolumeAdvisor::advice_at(double c, FrameAdvice& advice) {
  advice.quality = balance::quality_of(c, config_.targeting.space);
  advice.predicted_ms = predict_ms(c);
  if (!std::isfinite(advice.predicted_ms)) advice.predicted_ms = 0;
  // The work of each pixel at the chosen step, in samples; sigma is per such sample.
  advice.pixel_work.resize(samples_.size());
  const float inv_step = float(1 / advice.quality.step_scale);
  for (size_t i = 0; i < samples_.size(); ++i)
    advice.pixel_work[i] = samples_[i] * inv_step + fixed_[i];
  const CostFeatures x = features(advice.quality.step_scale);
  last_features_ = x;
  advice.device_cost.clear();
  for (size_t i = 0; i < models_.size(); ++i) {
    predicted_sigma_[i] = models_[i].predict(x);
    advice.device_cost.push_back(predicted_sigma_[i]);
  }
}

std::optional<FrameAdvice> VolumeAdvisor::second_pass(const FrameAdvice& first,
                                                      const FrameRecord& first_pass) {
  const std::optional<double> c = targeting_.second_pass(first_pass.frame_ms);
  if (!c || !style_) return std::nullopt;
  FrameAdvice second = first;
  advice_at(*c, second);
  return second;
}

void VolumeAdvisor::measured(const FrameAdvice& advice, const FrameRecord& record,
                             const balance::FrameStats& stats) {
  Stopwatch clock;
  targeting_.measured(record.frame_ms);
  std::fill(measured_sigma_.begin(), measured_sigma_.end(), 0.0);
  if (!style_ || !stats.shape.weighted()) return;
  const balance::FrameShape& shape = stats.shape;  // as rendered: scaled weights
  const CostFeatures x = features(advice.quality.step_scale);
  for (size_t i = 0; i < models_.size() && i < stats.devices.size(); ++i) {
    const balance::DeviceFrameStats& d = stats.devices[i];
    alive_[i] = d.alive;
    if (!d.alive) continue;
    double work = 0;  // predicted samples' worth of what device i rendered
    for (const balance::ItemReport& it : d.items) {
      const Rect& r = it.item.rect;
      for (int y = r.y0; y < r.y1; ++y)
        for (int xx = r.x0; xx < r.x1; ++xx)
          work += shape.pixel_weight[(size_t(it.item.view) * size_t(shape.height) + size_t(y)) *
                                         size_t(shape.width) +
                                     size_t(xx)];
    }
    if (work > 0 && d.time_ms > 0) {
      measured_sigma_[i] = d.time_ms / work;
      models_[i].train(x, measured_sigma_[i]);
    }
  }
  timings_.train_ms = clock.elapsed_ms();
}

}  // namespace multiray
