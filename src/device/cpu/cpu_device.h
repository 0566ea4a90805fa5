// CPU device: every CPU kernel (render/kernel.h) and foveated sampling, run by a
// oneTBB task arena of N threads, optionally pinned to given cores and optionally throttled
// by a cgroup CPU quota.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "device/device_loop.h"
#include "render/kernel.h"
#include "render/scene_cache.h"

namespace multiray {

struct CpuDeviceOptions {
  int threads = 1;
  std::vector<int> cores = {};  // empty: not pinned
  double speed = 1.0;           // emulated speed factor (idle after each unit), (0, 1]
  double quota = 0.0;           // fraction of one core per thread via cgroup v1; 0 = none
  int tile = 16;                // side of the pixel blocks handed to the threads
  int fail_after = -1;          // testing aid: fail when pulling an item after this many items
  bool compact = false;         // trace the compact scene representation
  uint64_t memory_limit = 0;    // emulated memory limit in bytes (mem=); 0: none
};

// Its frames run through the one device loop (device_loop.h): it supplies the rendering of
// one item (cut into tiles for its threads) and its arena.
class CpuDevice : public LoopDevice {
 public:
  // Uses the "embree" representation of `scenes` (shared by every CPU device: one BVH);
  // `scenes` must outlive the device.
  // Throws InputError when the options are impossible on this machine (e.g. core id out
  // of range) and DeviceError when a requested quota cannot be applied.
  CpuDevice(SceneCache& scenes, CpuDeviceOptions opts, std::string spec);
  ~CpuDevice() override;

  // Every CPU kernel, every sampling mode, on the "embree" representation.
  static DeviceCapabilities capabilities();

  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override;

  // Testing aids: how many times render() entered the device's task arena (once a frame),
  // and how many of its threads took items in the last frame (1 when it rendered items
  // one at a time).
  uint64_t arena_entries() const;
  int item_takers() const;

 private:
  class Items;  // the frame's rendering of one item, for the loop
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace multiray
