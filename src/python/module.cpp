// The `multiray` Python module: the Renderer and render() (renderer.cpp), image_hash and
// read_exr for comparing images with the CLI's, and multiray's errors as Python's:
// InputError -> ValueError, DeviceError -> RuntimeError, with the same one-line messages.
#include <cstdio>
#include <string>

#include "core/error.h"
#include "python/bindings.h"
#include "study/stats_json.h"

PYBIND11_MODULE(multiray, m) {
  using namespace multiray;
  using namespace multiray::python;
  m.doc() =
      "multiray from Python: render frames as NumPy arrays with the CLI's settings (see "
      "src/python/README.md).";
  m.attr("__version__") = study::kVersion;
  // Frames are NumPy arrays: without numpy the module would import and fail at the first
  // render with a bare "No module named 'numpy'" (a pyenv or virtualenv python3 first on
  // PATH lacks Debian's packages). Fail here, in one line naming both interpreters.
  try {
    py::module_::import("numpy");
  } catch (const py::error_already_set&) {
    const std::string here = py::module_::import("sys").attr("executable").cast<std::string>();
    throw py::import_error(
        "multiray was built for " MULTIRAY_PYTHON_EXECUTABLE
        " and needs numpy; this interpreter (" +
        here + ") has none: run " MULTIRAY_PYTHON_EXECUTABLE ", or install numpy for it");
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const DeviceError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  bind_renderer(m);
  bind_balance_types(m);
  bind_balancer(m);
  bind_trace(m);
  bind_studies(m);
  m.def(
      "image_hash",
      [](const py::object& images) {
        // One array, or the views of a frame in order (hashes chained as stats.json's).
        uint64_t h = 0xcbf29ce484222325ull;
        if (py::isinstance<py::array>(images)) {
          h = image_hash(from_numpy(images.cast<py::array>()), h);
        } else {
          for (const py::handle view : images) {
            if (!py::isinstance<py::array>(view))
              throw py::type_error("image_hash() takes an array or a list of arrays");
            h = image_hash(from_numpy(py::reinterpret_borrow<py::array>(view)), h);
          }
        }
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
        return std::string(hex);
      },
      py::arg("images"),
      "XXH3 (64 bit) over the float32 pixels as 16 hex digits: stats.json's image_hash of a frame "
      "(pass every view, in order, for a frame of several).");
  m.def(
      "read_exr",
      [](const std::string& path) {
        Framebuffer fb;
        {
          py::gil_scoped_release release;
          fb = read_exr(path);
        }
        return to_numpy(fb);
      },
      py::arg("path"), "The R, G, B channels of an EXR file as an H×W×3 float32 array.");
}
