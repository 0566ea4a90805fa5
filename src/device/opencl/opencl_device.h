// OpenCL device: the path tracer of render/ as one OpenCL kernel (kernels/*.cl), on any
// OpenCL device — GPUs in the field, the CPU through PoCL here. The scene (flat BVH built
// on the host, shading records, materials, lights, textures) is uploaded once when the
// device is created; each work unit is then rendered by kernel launches of at most
// tile x tile pixels, timed on the host around enqueue + finish.
//
// Images are the CPU's statistically (same materials, lights, RNG streams) and exactly
// the same on every device of one OpenCL type whatever the split, because every pixel is
// a pure function of (pixel, sample, frame, view, seed).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "device/device.h"
#include "render/scene_cache.h"

namespace multiray {

struct OpenClDeviceOptions {
  int index = 0;             // global device index over all platforms (`opencl:N`)
  double speed = 1.0;        // emulated speed in (0, 1]: idles after each unit
  int tile = 256;            // side of the largest square one kernel launch renders
  int work_group = 64;       // work-group size, clamped to what the kernel allows
  std::vector<int> cores{};  // pin the thread that drives the device (empty: not pinned)
  int fail_after = -1;       // testing aid: fail when pulling a unit after this many units
};

class OpenClDevice : public Device {
 public:
  // Flattens the "embree" representation of `scenes` into its own buffers (`scenes` must
  // outlive the device). Throws InputError when `opts` are impossible here (no
  // such device index, bad values) and DeviceError when the device cannot be set up
  // (kernel build error with the compiler's log, scene too large, out of memory).
  OpenClDevice(SceneCache& scenes, OpenClDeviceOptions opts, std::string spec);
  ~OpenClDevice() override;

  // The path tracer only, uniform or per-pixel (adaptive) sampling.
  static DeviceCapabilities capabilities();

  const DeviceInfo& info() const override { return info_; }
  // Never throws: an OpenCL error (or the injected failure) returns failed = true, with
  // the units finished before it listed.
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override;
  void set_emulated_speed(double speed) override;

  // True when the kernel binary came from the on-disk cache (see cl_program.h).
  bool kernel_from_cache() const;
  // The work-group size in use after clamping.
  size_t work_group_size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  DeviceInfo info_;
};

}  // namespace multiray
