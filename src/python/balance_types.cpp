// The plain values a Python balancer reads and returns: WorkItem, FrameShape, Plan and
// the measured FrameStats (DeviceStats, ItemReport). WorkItem, FrameShape and the stats
// are multiray's own structs bound as they are (the stats read-only: a snapshot of one
// frame); a Plan holds Python lists, so that `plan.assigned[0].append(item)` does what it
// says, and is converted to balance::Plan when the balancer returns it.
#include <cmath>
#include <cstring>

#include "balance/plan.h"
#include "balance/stats.h"
#include "python/balance_py.h"

namespace multiray::python {

namespace {

using balance::FrameShape;

// multiray.Plan: the fields of balance::Plan, lists as Python lists.
struct PyPlan {
  py::list assigned;  // per device, a list of WorkItem
  py::list shared;
  py::list ratios;
  int batch = 1;
  bool steal = false;
  double image_scale = 1.0, step_scale = 1.0;
  bool pull_on_ready = false;
};

std::string type_name(const py::handle& v) {
  return py::str(py::type::of(v).attr("__name__")).cast<std::string>();
}

bool is_list(const py::handle& v) {
  return py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v);
}

// Any iterable (a tuple, a NumPy array of ratios) as a list of its elements; a list as is.
py::list as_list(const py::object& v, const char* what) {
  if (py::isinstance<py::str>(v) || !py::isinstance<py::iterable>(v))
    throw py::type_error(std::string("Plan.") + what + " must be a list, not " + type_name(v));
  return py::list(v);
}

std::vector<WorkItem> items_from(const py::handle& list, const std::string& what) {
  if (!is_list(list))
    throw py::type_error(what + " must be a list of multiray.WorkItem, not " + type_name(list));
  std::vector<WorkItem> items;
  items.reserve(py::len(list));
  size_t k = 0;
  for (const py::handle item : list) {
    if (!py::isinstance<WorkItem>(item))
      throw py::type_error(what + "[" + std::to_string(k) + "] is " + type_name(item) +
                           ", not a multiray.WorkItem");
    items.push_back(item.cast<const WorkItem&>());
    ++k;
  }
  return items;
}

py::list items_to(const std::vector<WorkItem>& items) {
  py::list out;
  for (const WorkItem& it : items) out.append(py::cast(it));
  return out;
}

std::string item_repr(const WorkItem& it) {
  const Rect& r = it.rect;
  return "WorkItem(view=" + std::to_string(it.view) + ", x0=" + std::to_string(r.x0) +
         ", y0=" + std::to_string(r.y0) + ", x1=" + std::to_string(r.x1) +
         ", y1=" + std::to_string(r.y1) + ")";
}

py::object weights_to_numpy(const FrameShape& s) {
  if (!s.weighted()) return py::none();
  py::array_t<float> a({py::ssize_t(s.views), py::ssize_t(s.height), py::ssize_t(s.width)});
  std::memcpy(a.mutable_data(), s.pixel_weight.data(), s.pixel_weight.size() * sizeof(float));
  return py::object(std::move(a));
}

FrameShape make_shape(int width, int height, int views, const py::object& weight,
                      const std::vector<double>& device_cost) {
  FrameShape s{width, height, views, {}, device_cost};
  if (!weight.is_none()) {
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(weight);
    if (!a) throw py::type_error("pixel_weight must be an array of numbers or None");
    s.pixel_weight.assign(a.data(), a.data() + a.size());
  }
  try {
    balance::validate_shape(s);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  return s;
}

void bind_work_item(py::module_& m) {
  py::class_<WorkItem>(m, "WorkItem",
                       "Pixels [x0, x1) × [y0, y1) of view `view`: the unit of work.")
      .def(py::init([](int view, int x0, int y0, int x1, int y1) {
             return WorkItem{Rect{x0, y0, x1, y1}, view};
           }),
           py::arg("view"), py::arg("x0"), py::arg("y0"), py::arg("x1"), py::arg("y1"))
      .def_readwrite("view", &WorkItem::view)
      .def_property(
          "x0", [](const WorkItem& w) { return w.rect.x0; },
          [](WorkItem& w, int v) { w.rect.x0 = v; })
      .def_property(
          "y0", [](const WorkItem& w) { return w.rect.y0; },
          [](WorkItem& w, int v) { w.rect.y0 = v; })
      .def_property(
          "x1", [](const WorkItem& w) { return w.rect.x1; },
          [](WorkItem& w, int v) { w.rect.x1 = v; })
      .def_property(
          "y1", [](const WorkItem& w) { return w.rect.y1; },
          [](WorkItem& w, int v) { w.rect.y1 = v; })
      .def_property_readonly("area", [](const WorkItem& w) { return w.rect.area(); })
      .def("__eq__", [](const WorkItem& a, const WorkItem& b) { return a == b; })
      .def("__hash__",
           [](const WorkItem& w) {
             return py::hash(py::make_tuple(w.view, w.rect.x0, w.rect.y0, w.rect.x1, w.rect.y1));
           })
      .def("__repr__", &item_repr);
}

void bind_shape(py::module_& m) {
  py::class_<FrameShape>(m, "FrameShape",
                         "What a frame asks for: `views` images of width×height pixels; "
                         "pixel_weight (views×height×width float32, a copy) or None when "
                         "every pixel costs the same; device_cost, per device ms per unit of "
                         "weight predicted (empty: none).")
      .def(py::init(&make_shape), py::arg("width"), py::arg("height"), py::arg("views") = 1,
           py::arg("pixel_weight") = py::none(), py::arg("device_cost") = std::vector<double>{})
      .def_readonly("width", &FrameShape::width)
      .def_readonly("height", &FrameShape::height)
      .def_readonly("views", &FrameShape::views)
      .def_property_readonly("pixel_weight", &weights_to_numpy)
      .def_readonly("device_cost", &FrameShape::device_cost)
      .def_property_readonly("pixels", &FrameShape::pixels)
      .def("__repr__", [](const FrameShape& s) {
        return "FrameShape(width=" + std::to_string(s.width) +
               ", height=" + std::to_string(s.height) + ", views=" + std::to_string(s.views) +
               (s.weighted() ? ", weighted)" : ")");
      });
}

void bind_stats(py::module_& m) {
  py::class_<ItemReport>(m, "ItemReport", "One item as a device rendered it (read-only).")
      .def_readonly("item", &ItemReport::item)
      .def_readonly("id", &ItemReport::id)
      .def_readonly("time_ms", &ItemReport::time_ms)
      .def_readonly("busy_ms", &ItemReport::busy_ms)
      .def_readonly("samples", &ItemReport::samples);
  using balance::DeviceFrameStats;
  py::class_<DeviceFrameStats>(m, "DeviceStats", "One device's frame (read-only).")
      .def_readonly("alive", &DeviceFrameStats::alive)
      .def_readonly("time_ms", &DeviceFrameStats::time_ms)
      .def_readonly("busy_ms", &DeviceFrameStats::busy_ms)
      .def_readonly("samples", &DeviceFrameStats::samples)
      .def_readonly("pixels", &DeviceFrameStats::pixels)
      .def_readonly("items", &DeviceFrameStats::items);
  using balance::FrameStats;
  py::class_<FrameStats>(m, "FrameStats",
                         "What the devices measured in one frame (read-only): frame, shape "
                         "and devices, a list of DeviceStats in device order.")
      .def_readonly("frame", &FrameStats::frame)
      .def_readonly("shape", &FrameStats::shape)
      .def_readonly("devices", &FrameStats::devices);
}

void bind_plan(py::module_& m) {
  py::class_<PyPlan>(m, "Plan",
                     "How a frame is split: `assigned`, per device a list of WorkItem taken "
                     "in order; `ratios`, per device the intended share (sum 1); `shared`, "
                     "items pulled `batch` at a time once a device's list is done; `steal`; "
                     "`image_scale` and `step_scale` (quality; 1 is full).")
      .def(py::init([](const py::object& assigned, const py::object& ratios,
                       const py::object& shared, int batch, bool steal, double image_scale,
                       double step_scale, bool pull_on_ready) {
             return PyPlan{as_list(assigned, "assigned"),
                           as_list(shared, "shared"),
                           as_list(ratios, "ratios"),
                           batch,
                           steal,
                           image_scale,
                           step_scale,
                           pull_on_ready};
           }),
           py::arg("assigned"), py::arg("ratios"), py::arg("shared") = py::list(),
           py::arg("batch") = 1, py::arg("steal") = false, py::arg("image_scale") = 1.0,
           py::arg("step_scale") = 1.0, py::arg("pull_on_ready") = false)
      .def_property(
          "assigned", [](const PyPlan& p) { return p.assigned; },
          [](PyPlan& p, const py::object& v) { p.assigned = as_list(v, "assigned"); })
      .def_property(
          "shared", [](const PyPlan& p) { return p.shared; },
          [](PyPlan& p, const py::object& v) { p.shared = as_list(v, "shared"); })
      .def_property(
          "ratios", [](const PyPlan& p) { return p.ratios; },
          [](PyPlan& p, const py::object& v) { p.ratios = as_list(v, "ratios"); })
      .def_readwrite("batch", &PyPlan::batch)
      .def_readwrite("steal", &PyPlan::steal)
      .def_readwrite("image_scale", &PyPlan::image_scale)
      .def_readwrite("step_scale", &PyPlan::step_scale)
      .def_readwrite("pull_on_ready", &PyPlan::pull_on_ready)
      .def("__eq__",
           [](const py::object& a, const py::object& b) {
             // Equal items in the same order, bit-equal ratios, the same settings.
             if (!py::isinstance<PyPlan>(b)) return false;
             const balance::Plan x = plan_from_python(a, "Plan"), y = plan_from_python(b, "Plan");
             return x.assigned == y.assigned && x.shared == y.shared && x.ratios == y.ratios &&
                    x.batch == y.batch && x.steal == y.steal &&
                    x.quality.image_scale == y.quality.image_scale &&
                    x.quality.step_scale == y.quality.step_scale &&
                    x.pull_on_ready == y.pull_on_ready;
           })
      .def("__repr__", [](const PyPlan& p) {
        return "Plan(assigned=" + py::repr(p.assigned).cast<std::string>() +
               ", ratios=" + py::repr(p.ratios).cast<std::string>() +
               ", shared=" + py::repr(p.shared).cast<std::string>() +
               ", batch=" + std::to_string(p.batch) + ", steal=" + (p.steal ? "True" : "False") +
               ")";
      });
}

}  // namespace

py::object plan_to_python(const balance::Plan& plan) {
  PyPlan p;
  for (const auto& list : plan.assigned) p.assigned.append(items_to(list));
  p.shared = items_to(plan.shared);
  for (double r : plan.ratios) p.ratios.append(r);
  p.batch = plan.batch, p.steal = plan.steal, p.pull_on_ready = plan.pull_on_ready;
  p.image_scale = plan.quality.image_scale, p.step_scale = plan.quality.step_scale;
  return py::cast(std::move(p));
}

balance::Plan plan_from_python(const py::handle& value, const std::string& who) {
  if (!py::isinstance<PyPlan>(value))
    throw py::type_error(who + " returned " + type_name(value) + ", not a multiray.Plan");
  const PyPlan& p = value.cast<const PyPlan&>();
  balance::Plan plan;
  size_t d = 0;
  for (const py::handle list : p.assigned)
    plan.assigned.push_back(
        items_from(list, who + ": plan.assigned[" + std::to_string(d++) + "]"));
  plan.shared = items_from(p.shared, who + ": plan.shared");
  for (const py::handle r : p.ratios) {
    if (!PyFloat_Check(r.ptr()) && !PyLong_Check(r.ptr()) && !PyNumber_Check(r.ptr()))
      throw py::type_error(who + ": plan.ratios holds " + type_name(r) + ", not a number");
    plan.ratios.push_back(r.cast<double>());
  }
  plan.batch = p.batch, plan.steal = p.steal, plan.pull_on_ready = p.pull_on_ready;
  plan.quality = balance::Quality{p.image_scale, p.step_scale};
  return plan;
}

void bind_balance_types(py::module_& m) {
  bind_work_item(m);
  bind_shape(m);
  bind_stats(m);
  bind_plan(m);
}

}  // namespace multiray::python
