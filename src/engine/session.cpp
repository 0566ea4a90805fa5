#include "engine/session.h"

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "core/error.h"

namespace multiray {

Session::Session(std::vector<Device*> devices,
                 std::vector<std::unique_ptr<balance::Balancer>> lanes, FrameViews views,
                 CameraPath path, RenderSettings settings)
    : devices_(std::move(devices)),
      views_(std::move(views)),
      path_(std::move(path)),
      settings_(settings) {
  if (lanes.empty()) throw InputError("a session needs at least one balancer");
  for (auto& balancer : lanes)
    engines_.push_back(std::make_unique<Engine>(devices_, std::move(balancer)));
  buffers_.resize(engines_.size());
}

void Session::set_perturbations(const std::vector<Perturbation>& p) {
  for (auto& e : engines_) e->set_perturbations(p);
}

void Session::set_advisors(const std::function<std::unique_ptr<FrameAdvisor>(size_t lane)>& make) {
  for (size_t lane = 0; lane < engines_.size(); ++lane)
    engines_[lane]->set_advisor(make ? make(lane) : nullptr);
}

void Session::set_camera(std::optional<Camera> camera) {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  camera_ = camera;
}

void Session::set_camera_path(CameraPath path) {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  path_ = std::move(path);
  camera_.reset();
}

Camera Session::camera_at(int frame) const {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  return camera_ ? *camera_ : path_.at(frame);
}

namespace {

bool same_camera(const Camera& a, const Camera& b) {
  const auto same = [](Vec3 u, Vec3 v) { return u.x == v.x && u.y == v.y && u.z == v.z; };
  return same(a.eye, b.eye) && same(a.target, b.target) && same(a.up, b.up) &&
         a.fov_y_deg == b.fov_y_deg && a.film_width == b.film_width &&
         a.film_height == b.film_height;
}

// Every setting another rank is sent, as text (fmt's shortest round-trip form, so equal
// text is equal value), and the volume style by identity: what decides a frame's image
// apart from the camera. A setting added to RenderSettings is in it by construction.
std::vector<std::string> setting_values(const RenderSettings& s) {
  std::vector<std::string> out;
  for_each_sent_setting(s,
                        [&](const char*, const auto& v) { out.push_back(fmt::format("{}", v)); });
  out.push_back(fmt::format("{}", static_cast<const void*>(s.volume_style.get())));
  return out;
}

}  // namespace

void Session::continue_sequence(int frame, const Camera& camera, FrameInput& input) {
  bool uniform = !input.reprojection;
  for (const ViewSetup& v : input.views) uniform &= !v.spp_map && !v.foveation;
  std::vector<std::string> settings = setting_values(settings_);
  const uint32_t spp = uint32_t(std::max(1, settings_.spp));
  if (uniform && last_full_quality_ && sequence_.frame >= 0 &&
      same_camera(camera, sequence_.camera) && settings == sequence_.settings &&
      sequence_.next <= UINT32_MAX - spp) {
    for (ViewSetup& v : input.views)
      v.first_sample = sequence_.next, v.sample_frame = uint32_t(sequence_.frame);
    sequence_.next += spp;
    return;
  }
  // This frame begins a sequence (first_sample 0: seeded by its own index).
  sequence_ = Sequence{uniform ? frame : -1, camera, std::move(settings), spp};
}

double Session::progress() const { return engines_[active_lane_.load()]->progress(); }

std::shared_ptr<FrameResult> Session::free_buffer(size_t lane) {
  // A buffer only the session references is free: no observer can read it any more.
  for (auto& b : buffers_[lane])
    if (b.use_count() == 1) return b;
  buffers_[lane].push_back(std::make_shared<FrameResult>());
  return buffers_[lane].back();
}

void Session::take_up_denoise() {
  const DenoiseMethod method = denoise_request_.load();
  if (method == denoise_) return;  // the same method: every lane keeps its history
  denoise_ = method;
  // New denoisers: the histories of the method before are dropped with them.
  denoisers_.clear();
  if (method != DenoiseMethod::none)
    denoisers_.assign(engines_.size(), FrameDenoiser(method, denoise_params_));
}

const std::vector<Framebuffer>* Session::scaled_for_denoise(size_t lane,
                                                            const FrameInput& input) const {
  return input.reprojection ? nullptr : engines_[lane]->scaled_images();
}

double Session::denoise_lane(size_t lane, const std::vector<ViewSetup>& views,
                             const std::vector<Framebuffer>* scaled, FrameResult& out) {
  FrameDenoiser& denoiser = denoisers_[lane];
  if (!scaled || out.images.empty()) return denoiser.apply(views, out.images, out.denoised);
  return denoiser.apply_scaled(views, *scaled, out.images[0].width, out.images[0].height,
                               out.denoised);
}

void Session::start_overlapped(size_t lane, const FrameInput& input,
                               std::shared_ptr<FrameResult> out) {
  // Copies: the next frame makes new views and renders into the engine's buffers.
  auto views = std::make_shared<const std::vector<ViewSetup>>(input.views);
  const std::vector<Framebuffer>* scaled = scaled_for_denoise(lane, input);
  auto small = scaled ? std::make_shared<const std::vector<Framebuffer>>(*scaled) : nullptr;
  FrameResult* r = out.get();
  overlapped_ = std::move(out);
  filter_job_.start([this, lane, views, small, r] {
    r->record.denoise_ms = denoise_lane(lane, *views, small.get(), *r);
  });
}

void Session::finish_overlapped(FrameObserver& observer) {
  if (!overlapped_) return;
  std::shared_ptr<FrameResult> out = std::move(overlapped_);
  overlapped_.reset();
  filter_job_.wait();
  observer.on_frame(out);
}

std::shared_ptr<FrameResult> Session::render_lane(size_t lane, int frame, FrameInput& input) {
  active_lane_ = lane;
  Engine& engine = *engines_[lane];
  std::shared_ptr<FrameResult> out = free_buffer(lane);
  out->lane = lane;
  out->frame = frame;
  out->sampling_ms = input.sampling_ms;
  out->reprojection = input.reprojection;
  out->record = engine.render_frame(frame, input.views, settings_, out->images);
  if (lane == 0)
    last_full_quality_ =
        out->record.quality.image_scale == 1.0 && out->record.quality.step_scale == 1.0;
  input.finish(out->images);
  out->denoised.clear();
  out->denoised_with = denoise_;
  if (!denoisers_.empty() && !overlapping())  // else run() starts it beside the next frame
    out->record.denoise_ms =
        denoise_lane(lane, input.views, scaled_for_denoise(lane, input), *out);
  out->plan = engine.last_plan();
  out->rendered = engine.last_rendered();
  out->stats = engine.last_stats();
  return out;
}

int Session::run(int first, int count, FrameObserver& observer) {
  // A stop requested before this call (a Ctrl-C right after the viewer printed its address)
  // must hold: the flag is cleared when run() returns, never when it starts.
  int done = 0;
  try {
    for (int frame = first; frame < first + count && !stop_; ++frame, ++done)
      run_frame(frame, observer);
  } catch (...) {
    // The frame being filtered was rendered: it is handed over before the error goes on.
    try {
      finish_overlapped(observer);
    } catch (...) {
    }
    stop_ = false;
    throw;
  }
  finish_overlapped(observer);
  stop_ = false;  // consumed: the next run() renders again
  return done;
}

void Session::run_frame(int frame, FrameObserver& observer) {
  const Camera camera = camera_at(frame);
  FrameInput input = views_.make(frame, camera);
  if (schedule_) schedule_(frame, settings_);
  if (progressive_) continue_sequence(frame, camera, input);
  observer.before_frame(frame, input);
  // Another method drops the denoisers: the one still filtering must end first.
  if (denoise_request_.load() != denoise_) finish_overlapped(observer);
  take_up_denoise();
  const size_t lanes = engines_.size();
  const size_t start = rotate_lanes_ && frame >= 0 ? (size_t(frame) + rotate_offset_) % lanes : 0;
  std::vector<std::shared_ptr<FrameResult>> held(rotate_lanes_ ? lanes : 0);
  for (size_t k = 0; k < lanes; ++k) {
    const size_t lane = (start + k) % lanes;
    const bool overlap = overlapping();
    std::shared_ptr<FrameResult> out = render_lane(lane, frame, input);
    if (overlap) {  // the frame before is handed over, this one filtered beside the next
      finish_overlapped(observer);
      start_overlapped(lane, input, std::move(out));
    } else if (rotate_lanes_) {
      held[lane] = std::move(out);
    } else {
      observer.on_frame(out);
    }
  }
  for (const auto& out : held) observer.on_frame(out);
}

}  // namespace multiray
