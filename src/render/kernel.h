// The kernel seam. A kernel renders the samples of rectangles of one view into that view's
// framebuffer and reports how many samples and rays it took; it never knows which device
// or balancer asked. Every pixel must be a pure function of (pixel, sample, frame, view,
// seed) and the scene representation, so that images do not depend on the split.
//
// CPU kernels are listed once, in cpu_kernels(): adding a kernel (a debug view, another
// integrator) is one class and one entry there; devices, the CLI's checks and `--help`
// read the list. Each entry says what it renders (triangles or a volume) and builds itself
// from the representation it needs in the SceneCache.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/render_types.h"
#include "render/scene_cache.h"
#include "util/rect.h"

namespace multiray {

class Kernel {
 public:
  virtual ~Kernel() = default;

  // Renders every pixel of `rect` into `out` (the view's full-size image): the view's
  // sample map or settings.spp samples per pixel. Safe to call concurrently for disjoint
  // rectangles.
  virtual KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                                  Framebuffer& out) const = 0;

  // One sample through each of samples[0..n) (the position is the sample, no jitter),
  // written to values[i]; random numbers keyed by (key, 0, frame, view, seed). Only for
  // kernels whose KernelEntry::point_samples is true (foveated sampling); the default
  // throws std::logic_error. Safe to call concurrently.
  virtual KernelStats render_samples(const ViewSetup& view, const RenderSettings& settings,
                                     const ImageSample* samples, size_t n, Vec3* values) const;
};

// What a kernel renders: a scene's triangles or its volume (Scene::volume).
enum class KernelInput { mesh, volume };

// What a kernel is, on whichever backend runs it: its name (RenderSettings::kernel,
// --integrator), a line of help, whether it can render samples at arbitrary positions
// (foveated sampling) and what it renders. Each backend's registry lists entries that add
// its own factory: the CPU's below, the OpenCL device's in device/opencl/opencl_kernels.h,
// whose names are CPU kernel names with the same input (so --integrator means one thing on
// every device; tests/opencl/opencl_kernels_test.cpp checks it). Capabilities
// (DeviceCapabilities::kernels) are read from the registries, never listed by hand.
struct KernelDescription {
  std::string name;
  std::string help;
  bool point_samples = false;
  KernelInput input = KernelInput::mesh;

  // True when the scene has what this kernel renders.
  bool accepts(const Scene& scene) const;
};

// One CPU kernel and how to build it from the representation it needs.
struct KernelEntry : KernelDescription {
  // `compact`: trace the compact representation (SceneCache::mesh); volumes ignore it.
  std::unique_ptr<Kernel> (*make)(SceneCache& scenes, bool compact) = nullptr;
};

// Every CPU kernel, in the order `--help` lists them.
const std::vector<KernelEntry>& cpu_kernels();
// The entry called `name`, or nullptr.
const KernelEntry* find_cpu_kernel(const std::string& name);

}  // namespace multiray
