// multiray.Renderer and multiray.render(): a run built from keyword arguments as the CLI's
// `render` builds it from its options (run/run.h build_run, Run::make_session), frames
// rendered by the same Session, handed to Python as NumPy arrays and stats.json's
// per-frame records. The GIL is released while a scene loads and while frames render.
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/core.h>

#include "core/error.h"
#include "engine/session.h"
#include "python/bindings.h"
#include "run/parse_options.h"
#include "run/run.h"
#include "study/stats_json.h"

namespace multiray::python {

namespace {

// Keeps the finished frames (the session then renders into other buffers) and, between
// frames, lets Python handle its signals: a Ctrl-C stops the run after the frame.
class Collector : public FrameObserver {
 public:
  explicit Collector(Session& session) : session_(session) {}
  void on_frame(const std::shared_ptr<const FrameResult>& result) override {
    frames.push_back(result);
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      interrupted = true;  // the exception stays set for the caller to raise
      session_.request_stop();
    }
  }
  std::vector<std::shared_ptr<const FrameResult>> frames;
  bool interrupted = false;

 private:
  Session& session_;
};

class Renderer {
 public:
  explicit Renderer(const py::kwargs& kwargs) {
    RenderArgs args = parse_render_kwargs(kwargs, "Renderer");
    config_ = args.config;
    if (config_.distributed.enabled)
      throw py::value_error("the Python module renders on this machine's devices only");
    std::vector<std::string> specs{apply_mapping(args.balancer, config_.mapping, "--balancer")};
    py::gil_scoped_release release;
    run_ = std::make_unique<Run>(build_run(config_, 1));
    session_ = run_->make_session(specs, "--balancer");
    if (run_->volume)  // as make_session's schedule, with set_transfer_function's choice
      session_->set_settings_schedule([this](int frame, RenderSettings& s) {
        run_->volume->apply(frame, s);
        std::lock_guard<std::mutex> lock(style_mutex_);
        if (style_) s.volume_style = style_;
      });
  }

  // Renders `count` frames (default: the `frames` argument) after those already rendered,
  // as a list of {"frame", "image" (view 0), "views" (every view), "stats"} dicts.
  py::list render(std::optional<int> count) {
    const int n = count.value_or(config_.frames);
    if (n < 0) throw py::value_error("render: frames must be 0 or more, not " + std::to_string(n));
    check_memory(n);
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    if (!busy.owns_lock())
      throw std::runtime_error("this Renderer is rendering in another thread");
    Collector collector(*session_);
    {
      py::gil_scoped_release release;
      next_frame_ += session_->run(next_frame_, n, collector);
    }
    if (collector.interrupted) throw py::error_already_set();
    py::list out;
    for (const auto& r : collector.frames) {
      py::list views;
      for (const Framebuffer& view : r->images) views.append(to_numpy(view));
      py::dict frame;
      frame["frame"] = r->frame;
      frame["image"] = views[0];
      frame["views"] = views;
      frame["stats"] = to_python(study::frame_result_to_json(*r));
      // aov=[...]: view 0's feature buffers by name (absent without aov).
      if (!config_.aovs.empty() && !r->images.empty())
        frame["aov"] = aovs_to_numpy(r->images[0].features, config_.aovs);
      // denoise="atrous"|"svgf": view 0 denoised ("image" stays the raw beauty).
      if (!r->denoised.empty()) frame["denoised"] = to_numpy(r->denoised[0]);
      out.append(frame);
    }
    return out;
  }

  // The camera of the following frames ("ex,ey,ez,tx,ty,tz,ux,uy,uz,fov", as --camera), or
  // None: back to the camera path.
  void set_camera(const std::optional<std::string>& camera) {
    session_->set_camera(camera ? std::optional<Camera>(parse_camera(*camera)) : std::nullopt);
  }

  // The camera path of the following frames: a --camera-path value ("fixed", "orbit",
  // "orbit:PERIOD", a JSON file) around the run's base camera, or keyframes as that file
  // holds them ({"keyframes": [...]} or the list alone). Drops a set_camera() camera.
  void set_camera_path(const py::object& path) {
    if (py::isinstance<py::str>(path)) {
      session_->set_camera_path(camera_path_option(path.cast<std::string>(), run_->camera));
      return;
    }
    if (!py::isinstance<py::dict>(path) && !py::isinstance<py::list>(path))
      throw py::type_error("set_camera_path() takes a str, a dict or a list of keyframes");
    const std::string text = py::module_::import("json")
                                 .attr("dumps")(path, py::arg("allow_nan") = false)
                                 .cast<std::string>();
    nlohmann::json doc = nlohmann::json::parse(text);
    if (doc.is_array()) doc = nlohmann::json{{"keyframes", doc}};
    session_->set_camera_path(CameraPath::from_json(doc, "set_camera_path"));
  }

  // Volumes: the transfer function of the following frames, as --tf takes it (a preset or
  // a JSON file), as that file holds it (a dict), or None: back to --tf (or the sequence's).
  void set_transfer_function(const py::object& tf) {
    if (!run_->volume) throw py::value_error("set_transfer_function: the scene is not a volume");
    std::shared_ptr<const VolumeStyle> style;
    if (py::isinstance<py::str>(tf)) {
      py::gil_scoped_release release;  // a table and histograms are built (ms to s)
      style = run_->volume->style(tf.cast<std::string>());
    } else if (py::isinstance<py::dict>(tf)) {
      const std::string text = py::module_::import("json")
                                   .attr("dumps")(tf, py::arg("allow_nan") = false)
                                   .cast<std::string>();
      py::gil_scoped_release release;
      style = run_->volume->style_from_json(text);
    } else if (!tf.is_none()) {
      throw py::type_error("set_transfer_function() takes a str, a dict or None");
    }
    std::lock_guard<std::mutex> lock(style_mutex_);
    style_ = style;
  }

  py::object devices() const { return to_python(study::devices_to_json(run_->devices)); }
  py::object balancer() const { return to_python(session_->engine(0).balancer().spec()); }
  std::vector<std::string> notes() const { return run_->notes; }
  int next_frame() const { return next_frame_; }
  std::string scene() const { return run_->scene->name; }

 private:
  // The frames a render(n) returns are copies held by Python: n of them, with the run,
  // must fit max_memory as the CLI's frames do (a refusal beats an out-of-memory kill).
  void check_memory(int n) const {
    const int views = run_->views->rig().view_count();
    const double floats = config_.aovs.empty() && config_.denoise == "none"
                              ? 3
                              : 3 + 8 + 3;  // radiance, feature buffers, denoised
    const double per_frame =
        double(views) * run_->res.width * run_->res.height * floats * 4 + 4096;
    const MemoryEstimate run =
        estimate_memory(config_, views, run_->res.width, run_->res.height, 1);
    const double need = run.total() + n * per_frame,
                 limit = parse_memory_limit(config_.max_memory);
    if (need > limit)
      throw InputError(memory_refusal(
          need, fmt::format("{} frames returned to Python, {:.1f} GB", n, n * per_frame / 1e9),
          limit));
  }

  RunConfig config_;
  std::unique_ptr<Run> run_;  // before session_: the session uses its devices
  std::unique_ptr<Session> session_;
  int next_frame_ = 0;
  std::mutex busy_;
  std::mutex style_mutex_;  // the schedule reads style_ on the rendering thread
  std::shared_ptr<const VolumeStyle> style_;
};

}  // namespace

void bind_renderer(py::module_& m) {
  const std::string names = render_kwarg_names();
  py::class_<Renderer>(m, "Renderer",
                       ("A scene loaded and its devices made, as `multiray render` does, "
                        "ready to render frames. Keyword arguments are the CLI's options with "
                        "'_' for '-': " +
                        names + ". Bad values raise ValueError with the CLI's message.")
                           .c_str())
      .def(py::init<const py::kwargs&>())
      .def("render", &Renderer::render, py::arg("frames") = py::none(),
           "Render `frames` more frames (default: the `frames` argument); a list of dicts "
           "{'frame', 'image' (H×W×3 float32, linear), 'views', 'stats'}, and with "
           "aov=['albedo', 'normal', 'depth', 'variance', 'emission'] (any subset) 'aov': "
           "view 0's feature buffers by name (albedo, normal and emission H×W×3, depth and "
           "variance H×W; "
           "docs/noise.md).")
      .def("set_camera", &Renderer::set_camera, py::arg("camera"),
           "The camera of the next frames, 'ex,ey,ez,tx,ty,tz,ux,uy,uz,fov', or None for the "
           "camera path.")
      .def("set_camera_path", &Renderer::set_camera_path, py::arg("path"),
           "The camera path of the next frames: a --camera-path value ('fixed', 'orbit', "
           "'orbit:PERIOD', a JSON file) around the scene's camera, or keyframes "
           "[{'frame': 0, 'eye': [x, y, z], 'target': [...], 'up': [...], 'fov': 45}, ...] "
           "(or {'keyframes': [...]}); a camera set with set_camera is dropped.")
      .def("set_transfer_function", &Renderer::set_transfer_function, py::arg("tf"),
           "Volumes: the transfer function of the next frames, as --tf takes it (a preset "
           "such as 'angio' or a JSON file), as that file holds it (a dict: "
           "docs/volumes.md), or None for --tf again.")
      .def_property_readonly("devices", &Renderer::devices)
      .def_property_readonly("balancer", &Renderer::balancer)
      .def_property_readonly("notes", &Renderer::notes)
      .def_property_readonly("scene", &Renderer::scene)
      .def_property_readonly("next_frame", &Renderer::next_frame);
  m.def(
      "render",
      [](const py::kwargs& kwargs) {
        Renderer r(kwargs);
        return r.render(std::nullopt);
      },
      ("Render as `multiray render` does and return the frames: a list of dicts {'frame', "
       "'image' (H×W×3 float32, linear radiance), 'views' (every view), 'stats' (stats.json's "
       "record of the frame)}, and with aov=[...] 'aov' (feature buffers by name, "
       "Renderer.render). Keyword arguments: " +
       names + ".")
          .c_str());
}

}  // namespace multiray::python
