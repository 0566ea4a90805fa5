// Traces from Python: multiray.read_trace(path) and multiray.replay(trace, balancer), which
// runs a recorded trace through a balancer (a spec, registered Python ones included, or a
// multiray.Balancer instance) on simulated devices with balance::replay_trace_each, so the
// plans of two balancers can be compared frame by frame on the same recorded costs.
#include <chrono>
#include <fstream>

#include "balance/trace.h"
#include "python/balance_py.h"

namespace multiray::python {

namespace {

using TracePtr = std::shared_ptr<const balance::Trace>;

// Forwards to a balancer and times its last plan() and update() (ms, steady clock): what
// a frame pays for its balancer, GIL, conversions and check_plan included for Python ones.
class Timed final : public balance::Balancer {
 public:
  explicit Timed(std::unique_ptr<balance::Balancer> inner) : inner_(std::move(inner)) {}
  std::string name() const override { return inner_->name(); }
  std::string spec() const override { return inner_->spec(); }
  balance::Plan plan(const balance::FrameShape& shape, int frame) override {
    const auto t0 = Clock::now();
    balance::Plan p = inner_->plan(shape, frame);
    plan_ms = ms_since(t0);
    return p;
  }
  void update(const balance::FrameStats& stats) override {
    const auto t0 = Clock::now();
    inner_->update(stats);
    update_ms = ms_since(t0);
  }
  void drop_device(int index) override { inner_->drop_device(index); }
  balance::CutAxis cut_axis() const override { return inner_->cut_axis(); }
  void reset() { inner_.reset(); }

  double plan_ms = 0, update_ms = 0;

 private:
  using Clock = std::chrono::steady_clock;
  static double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }
  std::unique_ptr<balance::Balancer> inner_;
};

TracePtr load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw py::value_error("cannot open trace '" + path + "'");
  try {
    return std::make_shared<const balance::Trace>(balance::read_trace(in));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(path + ": " + e.what());
  }
}

py::list replay(const TracePtr& trace, const py::object& balancer, int frames, uint64_t seed) {
  if (frames < 0) throw py::value_error("replay: frames must be 0 or more");
  const int devices = int(trace->devices.size());
  std::unique_ptr<balance::Balancer> b;
  if (py::isinstance<py::str>(balancer)) {
    const std::string spec = balancer.cast<std::string>();
    py::gil_scoped_release release;  // a registered Python factory takes it back
    b = balance::make_balancer(spec, devices);
  } else {
    b = wrap_python_balancer(balancer);
    const int own = balancer.attr("devices").cast<int>();
    if (own != devices)
      throw py::value_error("replay: the balancer is for " + std::to_string(own) +
                            " devices, the trace has " + std::to_string(devices));
  }
  Timed timed(std::move(b));
  std::vector<balance::SimFrame> run;
  std::vector<std::pair<double, double>> ms;  // plan, update
  {
    py::gil_scoped_release release;
    balance::replay_trace_each(*trace, timed, {}, {}, frames, seed,
                               [&](int, balance::SimFrame&& f) {
                                 run.push_back(std::move(f));
                                 ms.emplace_back(timed.plan_ms, timed.update_ms);
                               });
    timed.reset();  // a Python balancer's adapter takes the GIL to let go of it
  }
  py::list out;
  for (size_t k = 0; k < run.size(); ++k) {
    balance::SimFrame& f = run[k];
    py::dict d;
    d["plan_ms"] = ms[k].first;
    d["update_ms"] = ms[k].second;
    d["frame"] = f.stats.frame;
    d["plan"] = plan_to_python(f.plan);
    d["frame_ms"] = f.frame_ms;
    py::list times;
    for (const balance::DeviceFrameStats& s : f.stats.devices) times.append(s.time_ms);
    d["times_ms"] = times;
    d["stats"] = py::cast(std::move(f.stats));
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_trace(py::module_& m) {
  py::class_<balance::Trace, std::shared_ptr<balance::Trace>>(
      m, "Trace",
      "A recorded trace (docs/traces.md): `balancer` (the spec it was recorded with), "
      "`devices` (a list of {'name', 'speed'}), len(trace) frames, trace[i] a FrameStats.")
      .def_readonly("balancer", &balance::Trace::balancer)
      .def_property_readonly(
          "devices",
          [](const balance::Trace& t) {
            py::list out;
            for (const balance::TraceDevice& d : t.devices)
              out.append(py::dict(py::arg("name") = d.name, py::arg("speed") = d.speed));
            return out;
          })
      .def("__len__", [](const balance::Trace& t) { return t.frames.size(); })
      .def("__getitem__", [](const balance::Trace& t, long long i) {
        const long long n = (long long)t.frames.size();
        if (i < 0) i += n;
        if (i < 0 || i >= n) throw py::index_error("trace frame index out of range");
        return t.frames[size_t(i)];
      });
  m.def(
      "read_trace",
      [](const std::string& path) {
        TracePtr t;
        {
          py::gil_scoped_release release;
          t = load(path);
        }
        return std::const_pointer_cast<balance::Trace>(t);
      },
      py::arg("path"), "A trace written by `multiray render --trace PATH`; ValueError if bad.");
  m.def(
      "replay",
      [](const std::shared_ptr<balance::Trace>& trace, const py::object& balancer, int frames,
         uint64_t seed) { return replay(trace, balancer, frames, seed); },
      py::arg("trace"), py::arg("balancer"), py::arg("frames") = 0, py::arg("seed") = 0,
      "Replays `trace` through `balancer` (a spec such as 'cycles', or a multiray.Balancer "
      "for the trace's device count) on simulated devices at the recorded speeds, each item "
      "costing what the trace recorded: `frames` frames (0: the trace's). Per frame a dict "
      "{'frame', 'plan' (a Plan), 'frame_ms', 'times_ms' (per device), 'stats' (FrameStats), "
      "'plan_ms', 'update_ms' (the balancer's own time for the frame, wall clock)}.");
}

}  // namespace multiray::python
