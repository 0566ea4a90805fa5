#include "render/kernel.h"

#include <stdexcept>

#include "render/ambient_occlusion.h"
#include "render/depth_kernel.h"
#include "render/direct_lighting.h"
#include "render/path_tracer.h"
#include "render/volume_raycaster.h"

namespace multiray {

KernelStats Kernel::render_samples(const ViewSetup&, const RenderSettings&, const ImageSample*,
                                   size_t, Vec3*) const {
  throw std::logic_error("this kernel cannot render samples at arbitrary image positions");
}

namespace {
template <class K>
std::unique_ptr<Kernel> make(SceneCache& scenes, bool compact) {
  return std::make_unique<K>(scenes.mesh(compact));
}
}  // namespace

const std::vector<KernelEntry>& cpu_kernels() {
  static const std::vector<KernelEntry> entries{
      {{"path", "path tracing with next-event estimation and MIS", true, KernelInput::mesh},
       &make<PathTracer>},
      {{"direct",
        "direct illumination: one light and one BSDF sample with MIS at the first surface "
        "(the path tracer stopped after one bounce; --bounces is ignored)",
        true, KernelInput::mesh},
       &make<DirectLighting>},
      {{"ao", "ambient occlusion (--ao-rays, --ao-distance)", true, KernelInput::mesh},
       &make<AmbientOcclusion>},
      {{"depth", "distance to the first surface, one ray per pixel (debugging)", true,
        KernelInput::mesh},
       &make<DepthKernel>},
      {{"volume", "volume raycasting (Bruder et al. 2017): --tf, --step", false,
        KernelInput::volume},
       &make_volume_raycaster},
  };
  return entries;
}

bool KernelDescription::accepts(const Scene& scene) const {
  return input == KernelInput::volume ? scene.volume != nullptr : scene.has_triangles();
}

const KernelEntry* find_cpu_kernel(const std::string& name) {
  for (const KernelEntry& e : cpu_kernels())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace multiray
