// The host side of the OpenCL path tracer (kernels/path_tracer.cl): the scene flattened
// into its own buffers (BVH built on the host, shading records, materials, lights,
// textures; or the compact scene's quantized mesh and tree when the RenderScene has one),
// uploaded once, then launches of up to tile x tile pixels, each a batch of rects
// (cl_runtime.h, plan_launches).
#pragma once

#include <memory>

#include "device/opencl/cl_runtime.h"

namespace multiray {

// Flattens `rs` and uploads it to `rt`'s device (`rt` and `rs` must outlive the result).
// Throws DeviceError (kernel build error, buffer too large) or cl::Error.
std::unique_ptr<ClKernelRunner> make_cl_path_tracer(const ClRuntime& rt, const RenderScene& rs);

}  // namespace multiray
