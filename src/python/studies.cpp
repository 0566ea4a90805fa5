// multiray.simulate() and multiray.bench(): the CLI's `simulate TRACE --json F` and
// `bench ... --json F` documents as plain Python data, made by the same library functions
// (study/simulate_study.h, study/bench_run.h), quietly. The GIL is released while studies run
// and frames render; Ctrl-C is checked between studies (simulate) and before each frame
// (bench), and raises KeyboardInterrupt with nothing returned.
#include <string>
#include <vector>

#include "python/bindings.h"
#include "study/bench_run.h"
#include "study/simulate_calibrated.h"
#include "study/simulate_study.h"

namespace multiray::python {

namespace {

// Thrown on the worker side when Python has a pending signal (its exception stays set).
struct Interrupted {};

// A pending Ctrl-C (or another signal whose Python handler raised), checked with the GIL.
bool signalled() {
  py::gil_scoped_acquire gil;
  return PyErr_CheckSignals() != 0;
}

// `devices=[2, 4, 8]` and `balancers=["uniform", "queue"]` as the CLI's comma-separated
// text; any other value is left for assign_kwargs to check.
py::kwargs join_lists(const py::kwargs& kwargs, const char* caller) {
  py::kwargs out;
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key).cast<std::string>();
    const bool list = py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value);
    if (!list || (name != "devices" && name != "balancers" && name != "predict")) {
      out[key] = value;
      continue;
    }
    std::string text;
    for (const py::handle item : value) {
      const bool ok = name == "devices"
                          ? py::isinstance<py::int_>(item) && !py::isinstance<py::bool_>(item)
                          : py::isinstance<py::str>(item);
      if (!ok)
        throw py::type_error(std::string(caller) + "(): " + name + " must be a str or a list of " +
                             (name == "devices" ? "int" : "str") + ", not a list holding " +
                             std::string(py::str(py::type::of(item).attr("__name__"))));
      if (!text.empty()) text += ',';
      text += py::str(item).cast<std::string>();
    }
    out[key] = py::str(text);
  }
  return out;
}

py::object simulate(const py::object& trace_path, const py::kwargs& kwargs) {
  study::SimulateOptions o;
  if (!py::isinstance<py::str>(trace_path) && !py::hasattr(trace_path, "__fspath__"))
    throw py::type_error("simulate(): trace_path must be a str or os.PathLike, not " +
                         std::string(py::str(py::type::of(trace_path).attr("__name__"))));
  o.trace_path = py::str(py::module_::import("os").attr("fspath")(trace_path)).cast<std::string>();
  assign_kwargs(join_lists(kwargs, "simulate"),
                {{"devices", &o.devices},
                 {"speeds", &o.speeds},
                 {"noise", &o.noise},
                 {"slowdown", &o.slowdown},
                 {"link", &o.link},
                 {"result_encoding", &o.results},
                 {"zstd_ratio", &o.zstd_ratio},
                 {"balancers", &o.balancers},
                 {"frames", &o.frames},
                 {"warmup", &o.warmup},
                 {"seed", &o.seed},
                 {"max_memory", &o.max_memory},
                 {"calibrate", &o.calibrate},
                 {"predict", &o.predict},
                 {"contention", &o.contention},
                 {"calibration", &o.calibration}},
                "simulate");
  nlohmann::json doc;
  try {
    py::gil_scoped_release release;
    const balance::Trace trace = study::load_trace(o.trace_path);
    if (o.calibrate || !o.predict.empty() ||
        o.calibration != "single") {  // as --calibrate [--predict]: its document
      doc = study::calibrated_study(trace, study::calibrated_run(o), false);
    } else {
      study::SimulationPlan plan = study::plan_simulation(o, trace, true);
      const auto results = study::run_simulation(trace, plan, [](const std::string&, const auto&) {
        if (signalled()) throw Interrupted{};
      });
      doc = study::simulation_to_json(o, plan, results);
    }
  } catch (const Interrupted&) {
    throw py::error_already_set();
  }
  return to_python(doc);
}

py::object bench(const py::object& scene, const py::kwargs& kwargs) {
  RenderArgs args;
  args.config = study::bench_defaults();
  study::BenchOptions b;
  std::map<std::string, Field> table = render_fields(args);
  table.erase("balancer");  // bench compares `balancers`
  table.insert({{"balancers", &b.balancers},
                {"report", &b.report_dir},
                {"trace", &b.trace_prefix},
                {"warmup", &b.warmup},
                {"ideal_frames", &b.ideal_frames},
                {"repeats", &b.repeats},
                {"probe_ms", &b.probe_ms}});
  if (!scene.is_none()) assign_kwargs(py::dict(py::arg("scene") = scene), table, "bench");
  assign_kwargs(join_lists(kwargs, "bench"), table, "bench");
  b.warmup_given = kwargs.contains("warmup");
  b.repeats_given = kwargs.contains("repeats");
  study::BenchHooks hooks;
  hooks.quiet = true;
  hooks.document = true;
  hooks.before_frame = [] { return !signalled(); };
  study::BenchOutcome out;
  {
    py::gil_scoped_release release;
    out = study::run_bench_study(args.config, b, hooks);
  }
  if (out.interrupted) throw py::error_already_set();
  // The CLI's exit code 1; the document says where. A warnings filter may make it an error.
  if (!out.mismatch.empty() &&
      PyErr_WarnEx(
          PyExc_RuntimeWarning,
          ("images differ between balancers rendering at the same quality: " + out.mismatch)
              .c_str(),
          1) < 0)
    throw py::error_already_set();
  return to_python(out.doc);
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("simulate", &simulate, py::arg("trace_path"),
        "Replay a trace (written by render/bench --trace) on virtual devices with balancers, "
        "in virtual time, as `multiray simulate TRACE --json F` does, and return that "
        "document: a dict with the settings and 'runs' (one dict per device count and "
        "balancer). Keyword arguments are the CLI's options with '_' for '-': devices (str "
        "or list of int), speeds, noise, slowdown, link, result_encoding, zstd_ratio, "
        "balancers (str or list of str), frames, warmup, seed, max_memory. With "
        "calibrate=True (or predict=[real traces]) the simulator is first calibrated on the "
        "trace and the document is that of `simulate TRACE --calibrate [--predict ...] "
        "--json F` ('calibration', 'rows'; contention, noise, warmup, seed and calibration "
        "('single', 'pooled' or 'leave-one-out', as --calibration) apply). Bad "
        "values raise ValueError with the CLI's message.");
  m.def(
      "bench", &bench, py::arg("scene") = py::none(),
      ("Run several balancers on the same frames as `multiray bench ... --json F` does and "
       "return that document (a dict; 'runs' holds one dict per balancer). Keyword "
       "arguments are the CLI's bench options with '_' for '-': balancers (str or list of "
       "str), warmup, ideal_frames, repeats, probe_ms, report, trace, and the render "
       "options but balancer: " +
       render_kwarg_names() + ". Quiet; images differing between balancers give a RuntimeWarning.")
          .c_str());
}

}  // namespace multiray::python
