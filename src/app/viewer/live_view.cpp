#include "app/viewer/live_view.h"

#include "core/composite.h"

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "balance/balancer.h"
#include "core/error.h"
#include "core/exposure.h"
#include "engine/volume_advisor.h"
#include "run/catalog.h"
#include "run/volume_run.h"
#include "study/stats_json.h"

namespace multiray::app::viewer {

namespace {
std::string error_json(const std::string& message) {
  return study::dump_json(nlohmann::json{{"type", "error"}, {"message", message}}, -1);
}
}  // namespace

LiveView::LiveView(Session& session, OrbitCamera camera, std::vector<std::string> device_names,
                   LiveViewOptions options)
    : session_(session),
      device_names_(std::move(device_names)),
      options_(std::move(options)),
      camera_(std::move(camera)),
      denoise_(options_.denoise) {
  if (options_.refine_spp > 0) {
    refinement_ = std::make_unique<Refinement>(options_.frame_spp, options_.refine_spp);
    session_.set_progressive(true);  // the frames averaged continue one sample sequence
  }
  if (options_.move_scale < 1.0) {
    motion_ = std::make_shared<MotionClock>();
    session_.set_advisors([clock = motion_, scale = options_.move_scale](size_t) {
      return std::make_unique<MotionAdvisor>(clock, scale);
    });
  }
  server_ = std::make_unique<WebServer>(
      options_.bind, options_.port, options_.max_clients, viewer_page(),
      [this] { return hello(); },
      [this](int client, const std::string& text) { handle(client, text); });
  if (options_.volume)
    session_.set_settings_schedule([this, v = options_.volume](int frame, RenderSettings& s) {
      std::lock_guard<std::mutex> lock(volume_mutex_);
      v->apply(frame, s);
      if (style_override_) s.volume_style = style_override_;
    });
  else if (options_.can_denoise)  // feature buffers while a denoiser is chosen
    session_.set_settings_schedule([this](int, RenderSettings& s) {
      s.feature_buffers = denoise_.choice() != DenoiseChoice::none;
    });
  sender_ = std::thread([this] { send_loop(); });
}

LiveView::~LiveView() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  sender_.join();
  server_.reset();
}

std::string LiveView::hello() const {
  nlohmann::json devices = nlohmann::json::array();
  for (const std::string& n : device_names_) devices.push_back(n);
  // dump_json: names (devices, a message quoting a client's text) may be any bytes.
  return study::dump_json(
      nlohmann::json{{"type", "hello"},
                     {"balancers", balance::balancer_names()},
                     {"balancer", session_.engine(0).balancer().name()},
                     {"devices", devices},
                     {"views", session_.views().rig().view_count()},
                     {"volume", options_.volume != nullptr},
                     {"ar", options_.ar},
                     {"denoise", denoise_name(denoise_.choice())},
                     {"can_denoise", options_.can_denoise},
                     {"presets", transfer_presets()},
                     {"target_ms", options_.volume ? options_.volume->options().target_ms : 0}},
      -1);
}

void LiveView::handle(int client, const std::string& text) {
  Command c;
  try {
    c = parse_command(text, int(session_.views().rig().view_count()));
    if (c.kind == Command::Kind::Balancer)  // checked here, applied between frames
      balance::make_balancer(c.spec, int(device_names_.size()));
  } catch (const std::exception& e) {  // InputError, or a bad balancer spec
    server_->send_text(client, error_json(e.what()));
    return;
  }
  if (c.kind == Command::Kind::Denoise) {
    if (!options_.can_denoise && c.denoise != DenoiseChoice::none)
      server_->send_text(client, error_json("this run cannot record the feature buffers a "
                                            "denoiser needs (the path integrator, uniform or "
                                            "adaptive sampling and no --ground can)"));
    else
      denoise_.choose(c.denoise);
    return;
  }
  if (c.kind == Command::Kind::Tf || c.kind == Command::Kind::Target) {
    const std::string error = volume_command(c);
    if (!error.empty()) server_->send_text(client, error_json(error));
    return;
  }
  if (c.kind == Command::Kind::Balancer || c.kind == Command::Kind::View) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (c.kind == Command::Kind::Balancer)
      balancer_request_ = c.spec;
    else
      view_ = c.view;
    return;
  }
  if (motion_) motion_->moved();
  std::lock_guard<std::mutex> lock(camera_mutex_);
  if (c.kind == Command::Kind::Orbit)
    camera_.orbit(c.x, c.y);
  else if (c.kind == Command::Kind::Pan)
    camera_.pan(c.x, c.y);
  else if (c.kind == Command::Kind::Zoom)
    camera_.zoom(c.x);
  else if (c.kind == Command::Kind::Look)
    camera_.look(c.x, c.y);
  else
    camera_.reset();
  session_.set_camera(camera_.camera());
}

std::string LiveView::volume_command(const Command& c) {
  if (!options_.volume) return "this run is not a volume";
  if (c.kind == Command::Kind::Target) {
    const auto* advisor = dynamic_cast<VolumeAdvisor*>(session_.engine(0).advisor());
    if (!advisor || !advisor->targets_frame_time())
      return "frame-time targeting is off: start multiray view with --adapt (e.g. --adapt "
             "last-frame --target-ms 50)";
    std::lock_guard<std::mutex> lock(mutex_);
    target_request_ = c.x;
    return "";
  }
  if (options_.distributed)
    return "the transfer function cannot change in a --distributed view: every rank builds "
           "its own from --tf";
  try {
    std::shared_ptr<const VolumeStyle> style;
    std::lock_guard<std::mutex> lock(volume_mutex_);
    if (!c.spec.empty()) {  // a preset by name; never a file named by the page
      const auto& names = transfer_presets();
      if (std::find(names.begin(), names.end(), c.spec) == names.end())
        return "unknown transfer-function preset '" + c.spec + "'";
      style = options_.volume->style(c.spec);
    } else {
      style = options_.volume->style_from_json(c.json);
    }
    style_override_ = style;
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void LiveView::before_frame(int frame, const FrameInput& input) {
  if (input.views.empty()) return;
  const Camera& camera = input.views.front().camera;
  // A frame is shown alone when the camera moved since the frame before (the refinement
  // starts again from it) or moves now (it is rendered smaller).
  const bool alone = !previous_camera_ ||
                     !(RefineKey{*previous_camera_, 0, 0} == RefineKey{camera, 0, 0}) ||
                     (motion_ && motion_->moving());
  previous_camera_ = camera;
  session_.set_denoise(options_.can_denoise ? denoise_.session_method(alone)
                                            : DenoiseMethod::none);
  std::lock_guard<std::mutex> lock(mutex_);
  frame_begun_[frame] = Begun{camera, input.views.front().first_sample};
}

LiveView::Shown LiveView::shown_image(const FrameResult& r, int view, const Begun* begun) {
  const Framebuffer& img = r.images.at(size_t(view));
  Shown out;
  if (begun) out.begun = *begun;
  const Framebuffer* refined = &img;  // as rendered
  bool restarted = true;
  if (refinement_ && begun) {  // the camera the frame was begun with is the key
    const double scale = r.record.quality.image_scale > 0 ? r.record.quality.image_scale : 1.0;
    refined = &refinement_->add(img, RefineKey{begun->camera, view, 0, scale});
    out.samples = refinement_->samples();
    restarted = refinement_->restarted();
  }
  out.image = denoise_.shown(r, size_t(view), *refined, out.samples, restarted, &out.denoised);
  return out;
}

void LiveView::on_frame(const std::shared_ptr<const FrameResult>& result) {
  Engine& engine = session_.engine(result->lane);
  int view = 0;
  std::optional<Begun> begun;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    view = std::min(view_, int(result->images.size()) - 1);
    // The camera the frame was begun with (set_camera may have moved it since).
    const auto it = frame_begun_.find(result->frame);
    if (it != frame_begun_.end()) begun = it->second;
    frame_begun_.erase(frame_begun_.begin(), frame_begun_.upper_bound(result->frame));
  }
  // Outside the lock: refining and filtering take a while, and only this thread does them.
  Shown shown = shown_image(*result, view, begun ? &*begun : nullptr);
  std::string request;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_) ++dropped_;
    pending_ = result;
    pending_view_ = view;
    pending_shown_ = std::move(shown);
    pending_balancer_ = engine.balancer().spec();  // the one that planned this frame
    request.swap(balancer_request_);
    if (target_request_ > 0)
      if (auto* advisor = dynamic_cast<VolumeAdvisor*>(engine.advisor()))
        advisor->set_target_ms(target_request_);
    target_request_ = 0;
  }
  wake_.notify_one();
  if (!request.empty())  // between frames, on the session's thread
    engine.set_balancer(balance::make_balancer(request, int(engine.device_count())));
}

std::string LiveView::frame_json(const FrameResult& r, int view, const std::string& balancer,
                                 const Shown& shown) const {
  const Camera& camera = shown.begun.camera;
  const FrameRecord& rec = r.record;
  nlohmann::json devices = nlohmann::json::array(), items = nlohmann::json::array();
  for (size_t d = 0; d < rec.devices.size(); ++d)
    devices.push_back({{"name", d < device_names_.size() ? device_names_[d] : ""},
                       {"time_ms", rec.devices[d].time_ms},
                       {"share", rec.devices[d].work_share},
                       {"alive", rec.devices[d].alive}});
  // What each device rendered of the streamed view, in output pixels.
  const double scale = rec.quality.image_scale > 0 ? 1.0 / rec.quality.image_scale : 1.0;
  for (size_t d = 0; d < r.rendered.size(); ++d)
    for (const balance::WorkItem& it : r.rendered[d])
      if (it.view == view)
        items.push_back({d, int(it.rect.x0 * scale), int(it.rect.y0 * scale),
                         int(it.rect.x1 * scale), int(it.rect.y1 * scale)});
  const Framebuffer& img = r.images.at(size_t(view));  // as rendered (the hash's image)
  const auto hex = [](uint64_t h) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", (unsigned long long)h);
    return std::string(text);
  };
  return study::dump_json(
      nlohmann::json{{"type", "frame"},
                     {"frame", r.frame},
                     {"view", view},
                     {"width", img.width},
                     {"height", img.height},
                     {"image_hash", hex(image_hash(img))},
                     {"shown_hash", hex(image_hash(*shown.image))},
                     {"denoise", denoise_name(shown.denoised)},
                     {"camera",
                      {{"eye", {camera.eye.x, camera.eye.y, camera.eye.z}},
                       {"target", {camera.target.x, camera.target.y, camera.target.z}}}},
                     {"frame_ms", rec.frame_ms},
                     {"imbalance", rec.imbalance},
                     {"balancer", balancer},
                     {"dropped", dropped_.load()},
                     {"spp", shown.samples},
                     {"first_sample", shown.begun.first_sample},
                     {"image_scale", rec.quality.image_scale},
                     {"refine_spp", refinement_ ? refinement_->target_spp() : 0},
                     {"devices", devices},
                     {"items", items}},
      -1);
}

void LiveView::send_loop() {
  for (;;) {
    std::shared_ptr<const FrameResult> frame;
    Shown shown;
    std::string balancer;
    int view = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_; });
      if (stop_) return;
      frame.swap(pending_);
      shown = std::move(pending_shown_);
      balancer = pending_balancer_;
      view = pending_view_;
    }
    if (server_->clients() == 0) continue;
    const Framebuffer& img = *shown.image;
    if (options_.meter_exposure) {  // this thread alone reads and writes options_.display
      options_.display.exposure_ev = metered_exposure_ev(img);
      options_.meter_exposure = false;
    }
    std::string jpeg;  // or, for an RGBA layer (a shadow catcher), a PNG with its alpha
    try {
      jpeg = img.alpha.empty()
                 ? encode_jpeg(img.width, img.height, to_srgb8(img, options_.display),
                               options_.jpeg_quality)
                 : encode_png_rgba(img.width, img.height, to_srgba8(img, options_.display));
    } catch (const std::exception&) {
      continue;  // an empty image; nothing to show
    }
    server_->broadcast_frame(std::make_shared<const OutFrame>(
        OutFrame{frame_json(*frame, view, balancer, shown), std::move(jpeg)}));
  }
}

}  // namespace multiray::app::viewer
