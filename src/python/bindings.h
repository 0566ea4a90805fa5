// The pieces of the `multiray` Python module (module.cpp declares it): conversions between
// multiray's values and Python's, the keyword arguments of a render, and the Renderer.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // std::optional, std::vector arguments and results
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "run/run_config.h"

namespace multiray::python {

namespace py = pybind11;

// A JSON document as plain Python data (dict, list, str, int, float, bool, None), through
// json.loads of its text: exactly the values stats.json would hold.
py::object to_python(const nlohmann::json& doc);

// A view as a new H×W×3 float32 array (linear radiance, row 0 at the top), a copy: the
// array does not keep the session's buffers alive.
py::array_t<float> to_numpy(const Framebuffer& fb);
// The feature buffers `names` (core/feature_buffers.h aov_names()) as new float32 arrays,
// {"albedo": H×W×3, "normal": H×W×3, "depth": H×W, "variance": H×W, "emission": H×W×3}.
py::dict aovs_to_numpy(const FeatureBuffers& f, const std::vector<std::string>& names);
// An H×W×3 array of float32 (any strides) as a Framebuffer; TypeError/ValueError otherwise.
Framebuffer from_numpy(const py::array& image);

// The settings of a render, from keyword arguments named as the CLI's options with '_'
// for '-' (res, spp, frames, devices, balancer, seed, camera, camera_path, ...; the scene
// as `scene`). Values are checked by build_run as the CLI's are; here only their Python
// types: TypeError for an unknown name or a value of the wrong type.
struct RenderArgs {
  RunConfig config;
  std::string balancer = "auto";
};
RenderArgs parse_render_kwargs(const py::kwargs& kwargs, const char* caller);
// The names parse_render_kwargs takes, for help texts.
std::string render_kwarg_names();

// Where a keyword argument goes: text (str, a number, os.PathLike), int, uint64_t (an int
// in [0, 2^64)), float, double, bool, or a list of str.
using Field =
    std::variant<std::string*, int*, float*, double*, bool*, std::vector<std::string>*, uint64_t*>;
// Stores each keyword argument into its field of `table`, checking only its Python type
// (TypeError naming `caller` for an unknown name or a wrong type; ValueError for an int
// out of range); the values are checked later, as the CLI checks them.
void assign_kwargs(const py::kwargs& kwargs, const std::map<std::string, Field>& table,
                   const char* caller);
// The keyword arguments of a render (parse_render_kwargs's table), into `args`.
std::map<std::string, Field> render_fields(RenderArgs& args);

// multiray.simulate() and multiray.bench() (studies.cpp).
void bind_studies(py::module_& m);

void bind_renderer(py::module_& m);
// Balancers in Python and traces (balance_types.cpp, balancer.cpp, trace_py.cpp).
void bind_balance_types(py::module_& m);
void bind_balancer(py::module_& m);
void bind_trace(py::module_& m);

}  // namespace multiray::python
