// The built-in backends' registry entries, one function per backend folder (cpu/,
// opencl/, ...). A new backend adds its folder, its entry function here and one line in
// backends.cpp; nothing outside device/ changes.
#pragma once

#include "device/device_factory.h"

namespace multiray {

BackendEntry cpu_backend();     // cpu/cpu_backend.cpp
BackendEntry opencl_backend();  // opencl/opencl_backend.cpp (listed as not built without OpenCL)

// The built-in entries, in the order `multiray devices` lists them.
std::vector<BackendEntry> builtin_backends();

}  // namespace multiray
