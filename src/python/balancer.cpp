// Balancers written in Python: the base class multiray.Balancer, the adapter that makes an
// instance a balance::Balancer for the engine, the simulator and replays, and
// multiray.register_balancer, which puts a Python factory in the process's registry so its
// name works wherever a balancer spec is taken (Renderer(balancer=...), replay()).
//
// The engine calls plan() before each frame and update() after it, on the thread that
// renders (the caller of Renderer.render, which released the GIL): the adapter takes the
// GIL for each call and lets it go before the devices start. Pulls from the shared queue
// and steals are served by the C++ Dispatcher; Python is never called per pull.
#include <cctype>
#include <climits>
#include <cstdio>
#include <variant>

#include "balance/plan.h"
#include "balance/registry.h"
#include "python/balance_py.h"

namespace multiray::python {

namespace {

// multiray.Balancer: holds the device count; the methods a subclass overrides.
struct BalancerBasePy {
  int devices = 1;
};

std::string class_name(const py::handle& obj) {
  return py::str(py::type::of(obj).attr("__name__")).cast<std::string>();
}

class PythonBalancer final : public balance::Balancer {
 public:
  PythonBalancer(const py::object& instance, int devices, std::string name, std::string spec)
      : instance_(instance.inc_ref().ptr()),
        devices_(devices),
        dropped_(size_t(devices), false),
        name_(std::move(name)),
        spec_(std::move(spec)) {}

  // The engine may drop its balancer on any thread; after Py_Finalize the reference leaks.
  ~PythonBalancer() override {
    if (!Py_IsInitialized()) return;
    py::gil_scoped_acquire gil;
    Py_DECREF(instance_);
  }

  std::string name() const override { return name_; }
  std::string spec() const override { return spec_; }

  balance::Plan plan(const balance::FrameShape& shape, int frame) override {
    balance::validate_shape(shape);
    balance::Plan plan;
    {
      py::gil_scoped_acquire gil;
      const py::object result = self().attr("plan")(shape, frame);
      plan = plan_from_python(result, class_name(self()) + ".plan()");
    }
    // O(n log n) in the items, without the GIL: Python threads run meanwhile.
    std::string wrong = balance::check_plan(plan, shape, devices_);
    if (wrong.empty()) wrong = dropped_given_work(plan);
    if (!wrong.empty())
      throw py::value_error("balancer " + name_ + ": the plan of frame " + std::to_string(frame) +
                            " is wrong: " + wrong);
    return plan;
  }

  void update(const balance::FrameStats& stats) override {
    for (size_t i = 0; i < stats.devices.size() && i < dropped_.size(); ++i)
      if (!stats.devices[i].alive) dropped_[i] = true;
    py::gil_scoped_acquire gil;
    self().attr("update")(stats);
  }

  void drop_device(int index) override {
    if (index < 0 || index >= devices_) return;  // as the contract says: ignored
    dropped_[size_t(index)] = true;
    py::gil_scoped_acquire gil;
    self().attr("drop_device")(index);
  }

 private:
  py::handle self() const { return instance_; }

  // The engine renders nothing for a dropped device: work planned for one would be lost
  // (the pixels left black), so such a plan is refused as a wrong one.
  std::string dropped_given_work(const balance::Plan& plan) const {
    for (size_t i = 0; i < dropped_.size(); ++i)
      if (dropped_[i] && (!plan.assigned[i].empty() || plan.ratios[i] != 0))
        return "device " + std::to_string(i) + " was dropped but is given work";
    return "";
  }

  PyObject* instance_;  // a reference of our own
  int devices_;
  std::vector<bool> dropped_;  // told by drop_device() or reported dead
  std::string name_, spec_;
};

// A registered balancer's option: its default decides how a spec's text is read.
using Default = std::variant<bool, long long, double, std::string>;

Default default_from(const std::string& key, const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) return v.cast<long long>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw py::type_error("register_balancer: the default of '" + key +
                       "' must be a bool, int, float or str, not " + class_name(v));
}

std::string default_text(const Default& d) {
  if (const bool* b = std::get_if<bool>(&d)) return *b ? "true" : "false";
  if (const long long* i = std::get_if<long long>(&d)) return std::to_string(*i);
  if (const double* x = std::get_if<double>(&d)) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", *x);
    return text;
  }
  return std::get<std::string>(d);
}

// The option `key` of `spec` read as its default's type (the range: what the type holds).
Default read_option(Spec& spec, const std::string& key, const Default& d) {
  if (const bool* b = std::get_if<bool>(&d)) return spec.get_bool(key, *b);
  if (const long long* i = std::get_if<long long>(&d))
    return (long long)spec.get_int(key, int(*i), INT_MIN, INT_MAX);
  if (const double* x = std::get_if<double>(&d)) return spec.get_double(key, *x, -1e308, 1e308);
  return spec.get_string(key, std::get<std::string>(d), {});
}

void register_python_balancer(const std::string& name, const py::object& factory,
                              const std::string& help, const py::dict& params) {
  if (!balance::valid_balancer_name(name))
    throw py::value_error("register_balancer: '" + name +
                          "' is not a balancer name (letters, digits, '-' and '_' only)");
  if (balance::find_balancer(name))
    throw py::value_error("register_balancer: '" + name + "' is already registered");
  if (!PyCallable_Check(factory.ptr()))
    throw py::type_error("register_balancer: the factory must be callable, not " +
                         class_name(factory));
  balance::BalancerEntry entry;
  entry.name = name;
  entry.help = help.empty() ? "a balancer written in Python" : help;
  entry.credit = "Python: " + py::repr(factory).cast<std::string>();
  std::vector<std::pair<std::string, Default>> options;
  for (const auto& [key, value] : params) {
    const std::string k = py::str(key).cast<std::string>();
    options.emplace_back(k, default_from(k, value));
    entry.params.push_back({k, default_text(options.back().second), "", "an option of " + name});
  }
  // The registry lives until the process exits, after the interpreter: it keeps a
  // reference that is never released (no Python object is destroyed after Py_Finalize).
  PyObject* held = factory.inc_ref().ptr();
  entry.make = [held, name, options](Spec& spec, int devices) {
    std::vector<std::pair<std::string, Default>> values;
    std::string text = name;
    for (const auto& [key, fallback] : options) {
      values.emplace_back(key, read_option(spec, key, fallback));
      text += ":" + key + "=" + default_text(values.back().second);
    }
    py::gil_scoped_acquire gil;
    py::dict kwargs;
    for (const auto& [key, value] : values)
      std::visit([&, k = key](const auto& v) { kwargs[py::str(k)] = v; }, value);
    const py::object instance = py::reinterpret_borrow<py::object>(held)(devices, **kwargs);
    return wrap_python_balancer(instance, name, text);
  };
  balance::register_balancer(std::move(entry));
}

}  // namespace

std::unique_ptr<balance::Balancer> wrap_python_balancer(const py::object& instance,
                                                        const std::string& name,
                                                        const std::string& spec) {
  if (!py::isinstance<BalancerBasePy>(instance))
    throw py::type_error("a Python balancer must be a multiray.Balancer, not " +
                         class_name(instance));
  const int devices = instance.cast<const BalancerBasePy&>().devices;
  const std::string own = name.empty() ? instance.attr("name")().cast<std::string>() : name;
  return std::make_unique<PythonBalancer>(instance, devices, own, spec.empty() ? own : spec);
}

void bind_balancer(py::module_& m) {
  py::class_<BalancerBasePy>(
      m, "Balancer", py::dynamic_attr(),
      "Base of balancers written in Python. Override plan(shape, frame) -> Plan (called "
      "before each frame) and update(stats) (after it, with the FrameStats measured); "
      "optionally drop_device(index) and name(). Call super().__init__(devices).")
      .def(py::init([](int devices) {
             if (devices < 1 || devices > 4096)
               throw py::value_error("a balancer is for 1..4096 devices, not " +
                                     std::to_string(devices));
             return BalancerBasePy{devices};
           }),
           py::arg("devices"))
      .def_readonly("devices", &BalancerBasePy::devices)
      .def("plan",
           [](const py::object& self, const py::object&, int) -> py::object {
             const std::string what = class_name(self) + " does not override plan(shape, frame)";
             PyErr_SetString(PyExc_NotImplementedError, what.c_str());
             throw py::error_already_set();
           })
      .def(
          "update", [](const py::object&, const py::object&) {}, py::arg("stats"))
      .def(
          "drop_device", [](const py::object&, int) {}, py::arg("index"))
      .def("name", [](const py::object& self) {
        std::string n = class_name(self);
        for (char& c : n) c = char(std::tolower(static_cast<unsigned char>(c)));
        return n;
      });
  m.def("register_balancer", &register_python_balancer, py::arg("name"), py::arg("factory"),
        py::arg("help") = "", py::arg("params") = py::dict(),
        "Registers `factory` (a multiray.Balancer subclass, or any callable returning an "
        "instance) under `name` for every balancer spec of this process: it is called as "
        "factory(devices, **options), the options being those of `params` (name -> default; "
        "a spec 'name:key=value' gives a value read as the default's type). ValueError for a "
        "name already registered, or not of letters, digits, '-' and '_' alone (a spec's "
        "grammar).");
  m.def(
      "balancer_names", [] { return balance::balancer_names(); },
      "Every balancer name a spec may use, the registered Python ones included.");
}

}  // namespace multiray::python
