// The host side of the OpenCL volume raycaster (kernels/volume.cl, the CPU's
// VolumeRaycaster step for step): the volume's values go to the device once, as floats;
// the frame's transfer table and per-block maximum opacities whenever
// RenderSettings::volume_style changes (a different shared_ptr); then launches of up to
// tile x tile pixels, each a batch of rects (cl_runtime.h, plan_launches).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "device/opencl/cl_runtime.h"
#include "render/volume_raycaster.h"

namespace multiray {

// Device memory the volume kernel takes for `vs` with launches of tile x tile pixels and
// a transfer table of `table_entries`, in bytes: the values (4 bytes a voxel, one
// buffer), the table, the block opacities, the launch buffers.
struct ClVolumeMemory {
  uint64_t values = 0, total = 0;
};
ClVolumeMemory cl_volume_memory(const VolumeScene& vs, int tile, size_t table_entries = 4096);

// Empty when `need` fits a device with `global_mem` bytes of global memory and buffers of
// at most `max_alloc` bytes; otherwise one line saying what is needed and what the device
// has.
std::string cl_volume_memory_problem(const ClVolumeMemory& need, uint64_t max_alloc,
                                     uint64_t global_mem);

// Checks the memory, builds the kernel and uploads the values of `vs` to `rt`'s device
// (`rt` and `vs` must outlive the result). Throws DeviceError (the volume does not fit,
// kernel build error) or cl::Error.
std::unique_ptr<ClKernelRunner> make_cl_volume_raycaster(const ClRuntime& rt,
                                                         const VolumeScene& vs);

}  // namespace multiray
