#include "device/opencl/opencl_kernels.h"

#include "device/opencl/opencl_path_tracer.h"
#include "device/opencl/opencl_volume.h"

namespace multiray {

namespace {
std::unique_ptr<ClKernelRunner> make_path(const ClRuntime& rt, SceneCache& scenes, bool compact) {
  return make_cl_path_tracer(rt, scenes.mesh(compact));
}
std::unique_ptr<ClKernelRunner> make_volume(const ClRuntime& rt, SceneCache& scenes, bool) {
  return make_cl_volume_raycaster(rt, volume_scene(scenes));
}
}  // namespace

const std::vector<ClKernelEntry>& opencl_kernels() {
  static const std::vector<ClKernelEntry> entries{
      {{"path",
        "the path tracer in OpenCL C (kernels/path_tracer.cl): flat or compact BVH, the same "
        "materials, lights and random numbers",
        false, KernelInput::mesh},
       &make_path},
      {{"volume", "the volume raycaster in OpenCL C (kernels/volume.cl), step for step", false,
        KernelInput::volume},
       &make_volume},
  };
  return entries;
}

const ClKernelEntry* find_opencl_kernel(const std::string& name) {
  for (const ClKernelEntry& e : opencl_kernels())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace multiray
