// The Khronos C++ bindings as this backend uses them (exceptions on, OpenCL 1.2 API, see
// src/device/opencl/CMakeLists.txt), plus device enumeration and error text. Private to
// src/device/opencl: no header outside this folder includes OpenCL.
#pragma once

#include <CL/opencl.hpp>

#include <string>
#include <vector>

namespace multiray::cl_util {

// Every device of every platform, platforms in the loader's order and devices in each
// platform's order: the global index N of the spec `opencl:N`. Empty (never throws) when
// there is no OpenCL platform or ICD.
std::vector<cl::Device> all_devices();

// "CL_OUT_OF_RESOURCES (-5)" for an OpenCL error code.
std::string error_name(cl_int code);

// One line naming the failed call and the error, e.g. "clEnqueueNDRangeKernel:
// CL_OUT_OF_RESOURCES (-5)".
std::string describe(const cl::Error& e);

}  // namespace multiray::cl_util
