// OpenCL device: the path tracer and the volume raycaster of render/ as OpenCL kernels
// (kernels/*.cl), on any OpenCL device — GPUs in the field, the CPU through PoCL here.
// It builds the kernels of its registry (opencl_kernels.h) that accept the scene, as the
// CPU device does with cpu_kernels(): for triangles the
// path tracer (opencl_path_tracer.h: flat BVH built on the host, shading records,
// materials, lights, textures), for a volume the raycaster (opencl_volume.h: the values,
// then the transfer table per style), uploaded once when the device is created; each work
// unit is then rendered by kernel launches of at most tile x tile pixels, timed on the
// host around enqueue + finish. Small units are taken and rendered in batches (`batch`:
// up to that many units of one view in one launch, cl_runtime.h's plan_launches) to pay
// a launch's fixed cost once per batch; each unit's time is then its share of the
// batch's, by samples.
//
// Images are the CPU's statistically (path tracer: same materials, lights, RNG streams;
// raycaster: the same arithmetic, expm1 rounding aside) and exactly the same on every
// device of one OpenCL type whatever the split, because every pixel is a pure function of
// (pixel, sample, frame, view, seed).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "device/device_loop.h"
#include "render/scene_cache.h"

namespace multiray {

struct OpenClDeviceOptions {
  int index = 0;                  // global device index over all platforms (`opencl:N`)
  double speed = 1.0;             // emulated speed in (0, 1]: idles after each unit
  int tile = 256;                 // side of the largest square one kernel launch renders
  int work_group = 64;            // work-group size, fitted to what each kernel allows
  bool work_group_given = false;  // `wg=` was given: a fitted size is noted (DeviceInfo::notes)
  int batch = 16;                 // items taken together and rendered in one launch, 1..64
  std::vector<int> cores{};       // pin the thread that drives the device (empty: not pinned)
  int fail_after = -1;            // testing aid: fail when pulling a unit after this many units
  bool compact = false;           // upload the compact scene representation (compact_scene.h)
  uint64_t memory_limit = 0;      // emulated device memory limit in bytes (mem=); 0: none
};

// Its frames run through the one device loop (device_loop.h): it supplies batches of items
// rendered by one launch each.
class OpenClDevice : public LoopDevice {
 public:
  // Uploads what its kernels need of `scenes` into its own buffers: the "embree"
  // representation flattened for a scene with triangles (or without a volume), or the
  // compact scene with opts.compact; the "volume" one for a volume (`scenes` must outlive
  // the device). Throws InputError when `opts` are impossible here (no such device index,
  // bad values, a scene over the emulated memory limit) and DeviceError when the
  // device cannot be set up (kernel build error with the compiler's log, scene or volume
  // too large, out of memory).
  OpenClDevice(SceneCache& scenes, OpenClDeviceOptions opts, std::string spec);
  ~OpenClDevice() override;

  // The kernels of opencl_kernels() (the path tracer and the volume raycaster), uniform or
  // per-pixel (adaptive) sampling. A device's info().caps lists only the kernels it built
  // for its scene.
  static DeviceCapabilities capabilities();

  // Never throws: an OpenCL error (or the injected failure) returns failed = true, with
  // the units finished before it listed.
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override;

  // True when every kernel binary came from the on-disk cache (see cl_program.h).
  bool kernel_from_cache() const;
  // The work-group size `kernel`'s launches use, fitted to what the compiled kernel
  // allows (ClRuntime::build_kernel); 0 for a kernel this device did not build.
  size_t work_group_size(const std::string& kernel) const;
  // CL_KERNEL_WORK_GROUP_SIZE of `kernel` as built (at least work_group_size); 0 likewise.
  size_t work_group_limit(const std::string& kernel) const;

 private:
  class Batches;  // the frame's batches, for the loop
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace multiray
