// The OpenCL device's kernels, listed once as the CPU's are (render/kernel.h): a kernel is
// a program under kernels/, a ClKernelRunner that launches it, and one entry here. The
// device builds the entries that accept its scene and runs RenderSettings::kernel, as the
// CPU device does; OpenClDevice::capabilities() reads its kernel names from this list.
//
// Every name is a CPU kernel's name with the same KernelInput: an OpenCL kernel is the
// CPU kernel of that name written in OpenCL C (statistically the same image), so
// `--integrator` means one thing on every device. tests/opencl/opencl_kernels_test.cpp
// checks it. Free of OpenCL's headers: the runner and runtime are only named here.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/kernel.h"

namespace multiray {

struct ClRuntime;      // cl_runtime.h
class ClKernelRunner;  // cl_runtime.h

struct ClKernelEntry : KernelDescription {
  // Builds the program on `rt`'s device and uploads the representation it needs of
  // `scenes` (`compact`: the compact mesh; volumes ignore it). `rt` and `scenes` must
  // outlive the runner. Throws DeviceError or cl::Error.
  std::unique_ptr<ClKernelRunner> (*make)(const ClRuntime& rt, SceneCache& scenes,
                                          bool compact) = nullptr;
};

// Every OpenCL kernel, in the order `multiray devices` lists them.
const std::vector<ClKernelEntry>& opencl_kernels();
// The entry called `name`, or nullptr.
const ClKernelEntry* find_opencl_kernel(const std::string& name);

}  // namespace multiray
