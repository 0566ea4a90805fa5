// compact_bench --opencl: the paper's like-for-like comparison on the OpenCL device, the
// same path-tracing kernel on the flat BVH and on the compact scene (opencl:0 against
// opencl:0:compact=1), alternately `reps` times; each frame's busy time as the device
// measures it around its kernel launches (medians), the scene buffers each device
// uploaded, and the PSNR between the two images. {"skipped": why} without a device or
// without the OpenCL backend.
#pragma once

#include <nlohmann/json.hpp>

#include "render/render_types.h"

namespace multiray {

nlohmann::json opencl_comparison(const Scene& scene, const ViewSetup& view,
                                 const RenderSettings& settings, int reps);

}  // namespace multiray
