// Conversions for the Python module: JSON and images to Python, keyword arguments to a
// RunConfig. Only Python types are checked here; every value is checked by build_run, so
// that a bad value gives the CLI's one-line message.
#include <algorithm>
#include <climits>
#include <cstring>
#include <functional>
#include <map>
#include <variant>

#include "python/bindings.h"
#include "study/stats_json.h"
#include "util/nearest.h"

namespace multiray::python {

py::object to_python(const nlohmann::json& doc) {
  return py::module_::import("json").attr("loads")(study::dump_json(doc, -1));
}

py::array_t<float> to_numpy(const Framebuffer& fb) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "Vec3 must be three packed floats");
  py::array_t<float> out({py::ssize_t(fb.height), py::ssize_t(fb.width), py::ssize_t(3)});
  std::memcpy(out.mutable_data(), fb.pixels.data(), fb.pixels.size() * sizeof(Vec3));
  return out;
}

Framebuffer from_numpy(const py::array& image) {
  if (!py::isinstance<py::array_t<float>>(image) || image.dtype().kind() != 'f' ||
      image.itemsize() != sizeof(float))
    throw py::type_error("image must be a float32 array, not " +
                         std::string(py::str(image.dtype())));
  if (image.ndim() != 3 || image.shape(2) != 3)
    throw py::value_error("image must be H×W×3, not of shape " +
                          std::string(py::str(image.attr("shape"))));
  if (image.shape(0) > INT_MAX || image.shape(1) > INT_MAX)
    throw py::value_error("image is too large");
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(image);
  Framebuffer fb(int(image.shape(1)), int(image.shape(0)));
  const float* src = a.data();
  for (Vec3& p : fb.pixels) p = Vec3(src[0], src[1], src[2]), src += 3;
  return fb;
}

namespace {

// A Python int, not a bool (True is an int to Python, never a count here).
bool is_int(const py::handle& v) {
  return py::isinstance<py::int_>(v) && !py::isinstance<py::bool_>(v);
}
bool is_number(const py::handle& v) { return is_int(v) || py::isinstance<py::float_>(v); }

[[noreturn]] void wrong_type(const char* caller, const std::string& name, const char* expected,
                             const py::handle& v) {
  throw py::type_error(std::string(caller) + "(): " + name + " must be " + expected + ", not " +
                       std::string(py::str(py::type::of(v).attr("__name__"))));
}

// Keyword -> the RunConfig member the CLI option of that name fills (app/common_options).
std::map<std::string, Field> fields(RenderArgs& a) {
  RunConfig& o = a.config;
  return {{"scene", &o.scene_path},
          {"res", &o.resolution},
          {"spp", &o.spp},
          {"bounces", &o.bounces},
          {"clamp", &o.clamp},
          {"frames", &o.frames},
          {"camera", &o.camera},
          {"up", &o.up},
          {"camera_path", &o.camera_path},
          {"devices", &o.devices},
          {"balancer", &a.balancer},
          {"seed", &o.seed},
          {"env", &o.env},
          {"env_scale", &o.env_scale},
          {"sun", &o.sun},
          {"perturb", &o.perturb},
          {"views", &o.views},
          {"view_spacing", &o.view_spacing},
          {"stereo", &o.stereo},
          {"mapping", &o.mapping},
          {"integrator", &o.integrator},
          {"tf", &o.volume.tf},
          {"step", &o.volume.step},
          {"raw", &o.volume.raw},
          {"target_ms", &o.volume.target_ms},
          {"adapt", &o.volume.adapt},
          {"adapt_space", &o.volume.adapt_space},
          {"prepass_stride", &o.volume.prepass_stride},
          {"cost_model", &o.volume.cost_model},
          {"reference_step", &o.volume.reference_step},
          {"sequence", &o.volume.sequence},
          {"ao_rays", &o.ao_rays},
          {"ao_distance", &o.ao_distance},
          {"sampling", &o.sampling},
          {"edge_spp", &o.edge_spp},
          {"reference_spacing", &o.reference_spacing},
          {"gaze", &o.gaze},
          {"gaze_path", &o.gaze_path},
          {"fovea_spp", &o.foveation.fovea_spp},
          {"fovea_radius", &o.foveation.fovea_radius},
          {"periphery_spp", &o.foveation.periphery_spp},
          {"allow_outside_paths", &o.allow_outside_paths},
          {"max_memory", &o.max_memory},
          {"aov", &o.aovs},
          {"denoise", &o.denoise},
          {"denoise_normal", &o.denoise_normal},
          {"svgf_history", &o.svgf_history}};
}

// Text options also take numbers (seed=7, step-like values) and paths (os.PathLike); the
// resolution also takes a (width, height) pair.
std::string text_value(const char* caller, const std::string& name, const py::handle& v) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (is_number(v)) return py::str(v).cast<std::string>();
  if (py::hasattr(v, "__fspath__")) return py::str(v.attr("__fspath__")()).cast<std::string>();
  if (name == "res" && py::isinstance<py::tuple>(v) && py::len(v) == 2) {
    const py::tuple t = v.cast<py::tuple>();
    if (is_int(t[0]) && is_int(t[1]))
      return py::str(t[0]).cast<std::string>() + "x" + py::str(t[1]).cast<std::string>();
  }
  wrong_type(caller, name, name == "res" ? "a str or a (width, height) pair" : "a str", v);
}

// A Python int in T's range (int, or uint64_t for seeds); ValueError otherwise (beyond
// 64 bits too).
template <class T>
T int_value(const char* caller, const std::string& name, const py::handle& v) {
  bool ok = false;
  T out{};
  if constexpr (std::is_same_v<T, int>) {
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    ok = overflow == 0 && n >= INT_MIN && n <= INT_MAX;
    out = T(n);
  } else {  // OverflowError below 0 or beyond 64 bits: cleared, reported as ours
    const unsigned long long n = PyLong_AsUnsignedLongLong(v.ptr());
    ok = !(n == static_cast<unsigned long long>(-1) && PyErr_Occurred());
    if (!ok) PyErr_Clear();
    out = T(n);
  }
  if (!ok)
    throw py::value_error(std::string(caller) + "(): " + name + " " +
                          py::str(v).cast<std::string>() + " is out of range");
  return out;
}

// " (did you mean 'spp'?)" for the table's key nearest `name`, or "".
std::string nearest_keyword(const std::string& name, const std::map<std::string, Field>& table) {
  std::vector<std::string> keys;
  for (const auto& entry : table) keys.push_back(entry.first);
  const std::string best = nearest_name(name, keys);
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

}  // namespace

void assign_kwargs(const py::kwargs& kwargs, const std::map<std::string, Field>& table,
                   const char* caller) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key).cast<std::string>();
    const auto it = table.find(name);
    if (it == table.end())
      throw py::type_error(std::string(caller) + "() got an unexpected keyword argument '" + name +
                           "'" + nearest_keyword(name, table));
    std::visit(
        [&](auto* field) {
          using T = std::remove_pointer_t<decltype(field)>;
          if constexpr (std::is_same_v<T, std::string>) {
            *field = text_value(caller, name, value);
          } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, uint64_t>) {
            if (!is_int(value)) wrong_type(caller, name, "an int", value);
            *field = int_value<T>(caller, name, value);
          } else if constexpr (std::is_same_v<T, bool>) {
            if (!py::isinstance<py::bool_>(value)) wrong_type(caller, name, "a bool", value);
            *field = value.cast<bool>();
          } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
            if (py::isinstance<py::str>(value)) {
              *field = {value.cast<std::string>()};
            } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
              field->clear();
              for (const py::handle item : value) {
                if (!py::isinstance<py::str>(item))
                  wrong_type(caller, name, "a list of str", item);
                field->push_back(item.cast<std::string>());
              }
            } else {
              wrong_type(caller, name, "a str or a list of str", value);
            }
          } else {  // float, double
            if (!is_number(value)) wrong_type(caller, name, "a number", value);
            *field = T(value.cast<double>());
          }
        },
        it->second);
  }
}

std::map<std::string, Field> render_fields(RenderArgs& args) { return fields(args); }

RenderArgs parse_render_kwargs(const py::kwargs& kwargs, const char* caller) {
  RenderArgs args;
  assign_kwargs(kwargs, fields(args), caller);
  // aov="albedo,normal" as --aov takes it (build_run checks the names).
  std::vector<std::string>& aovs = args.config.aovs;
  if (aovs.size() == 1 && aovs[0].find(',') != std::string::npos) {
    const std::string list = aovs[0];
    aovs.clear();
    for (size_t start = 0; start <= list.size();) {
      const size_t comma = std::min(list.find(',', start), list.size());
      aovs.push_back(list.substr(start, comma - start));
      start = comma + 1;
    }
  }
  return args;
}

py::dict aovs_to_numpy(const FeatureBuffers& f, const std::vector<std::string>& names) {
  py::dict out;
  for (const std::string& name : names) {
    const bool rgb = name == "albedo" || name == "normal" || name == "emission";
    const std::vector<float>& v = name == "albedo"     ? f.albedo
                                  : name == "normal"   ? f.normal
                                  : name == "depth"    ? f.depth
                                  : name == "emission" ? f.emission
                                                       : f.variance;
    std::vector<py::ssize_t> shape{py::ssize_t(f.height), py::ssize_t(f.width)};
    if (rgb) shape.push_back(3);
    py::array_t<float> a(shape);
    if (v.size() != size_t(a.size()))
      throw std::logic_error("feature buffer " + name + " does not match the frame");
    std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(float));
    out[py::str(name)] = a;
  }
  return out;
}

std::string render_kwarg_names() {
  RenderArgs a;
  std::string names;
  for (const auto& [name, field] : fields(a)) names += (names.empty() ? "" : ", ") + name;
  return names;
}

}  // namespace multiray::python
