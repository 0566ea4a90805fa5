// The Device interface: anything that renders work items of a frame and reports, from
// inside, how long it took. Backends live in sub-folders (cpu/, opencl/, ...) behind CMake
// options, each one entry of the registry (device_factory.h) whose frames run through the
// one device loop (device_loop.h); the engine sees only this header. A device states what it can
// do (DeviceCapabilities) so the CLI refuses an impossible job before any work starts.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/render_settings.h"
#include "util/rect.h"

namespace multiray {

// Slowest emulated speed a device or --perturb may ask for: a device idling 99% of the
// time. Slower ones would only make runs that never finish.
constexpr double kMinEmulatedSpeed = 0.01;

// What a backend can run. Names are those of RenderSettings::kernel (render/kernel.h),
// of --sampling, and of the scene representations in SceneCache. A backend fills
// `kernels` from its kernel registry (cpu_kernels(), opencl_kernels()) and `sampling`
// with sampling_modes().
struct DeviceCapabilities {
  std::vector<std::string> kernels;
  std::vector<std::string> sampling;  // "uniform", "adaptive", "foveated", "reproject"
  std::string representation;         // the scene representation this device renders
  // Renders RenderSettings' shadow catcher (--ground). Known from the backend's registry
  // entry, not sent to other ranks.
  bool shadow_catcher = false;
};

// The sampling modes of a backend: uniform, adaptive (per-pixel sample maps) and reproject
// for every kernel that renders rectangles; foveated only when `point_samples`, i.e. some
// kernel of its registry renders samples at arbitrary positions
// (KernelDescription::point_samples).
std::vector<std::string> sampling_modes(bool point_samples);

struct DeviceInfo {
  std::string type;  // the backend's registry name (device_factory.h), or "rank"
  std::string name;  // human readable, e.g. "cpu (1 thread, cores 0)"
  std::string spec;  // the --devices string that creates this device
  int threads = 1;
  double emulated_speed = 1.0;  // < 1: the device idles to mimic slower hardware (emulated)
  double cpu_quota = 0.0;       // > 0: real throttling by a cgroup CPU quota (fraction of a core)
  DeviceCapabilities caps;
  // The scene representation this device renders from ("embree", "compact",
  // "opencl-flat-bvh", "opencl-compact", "opencl-volume", ...) and its size in bytes
  // (0 when not known); `memory_limit` is the emulated limit of `mem=` (0: none).
  std::string representation;
  uint64_t scene_bytes = 0;
  uint64_t memory_limit = 0;
  // What the user should know about how the device was set up, one line each (e.g. an
  // OpenCL `wg=` larger than a kernel allows, rendered at a smaller size); the CLI prints
  // them as notes.
  std::vector<std::string> notes;
};

// Empty when a device with `info` can render frames of `kernel` with `sampling`;
// otherwise one line saying why not and what it supports.
std::string unsupported_job(const DeviceInfo& info, const std::string& kernel,
                            const std::string& sampling);

// Where a device gets its work during a frame. Implementations are thread-safe: all
// devices pull concurrently. Items are named by ids, echoed in ItemReport::id.
class WorkSource {
 public:
  virtual ~WorkSource() = default;
  // Starts the next item for `device`; false when nothing is left for it.
  virtual bool next(int device, uint32_t& id) = 0;
  // Starts up to `max` items in one request (one round trip for a device behind a link);
  // appends their ids to `ids` and returns how many. Default: next() repeatedly.
  virtual size_t next(int device, size_t max, std::vector<uint32_t>& ids);
  // Reserves up to `k` further items for `device` without starting them: they stay
  // stealable until a later next() starts them. Returns how many. Default: none.
  virtual size_t prefetch(int /*device*/, size_t /*k*/) { return 0; }
  // How many not-started items are `device`'s own already (its assigned list): a device
  // behind a link takes them in one request. Default: none known.
  virtual size_t pending(int /*device*/) const { return 0; }
  // True when a device behind a link is to hold one item pulled on demand at a time and
  // be sent the next only when it reports the last one rendered (balance::Plan::
  // pull_on_ready: Seo et al.'s strategy I). Default: false (the device's own depth).
  virtual bool pull_on_ready() const { return false; }
  // The item with id `id` (valid for the frame).
  virtual const WorkItem& item(uint32_t id) const = 0;
};

// Everything a device needs to render one frame: the views (cameras, sizes), the settings
// and where the pixels go. outputs[v] is view v's full-size image; devices write only the
// pixels of the items they pulled.
struct FrameJob {
  std::vector<ViewSetup> views;
  RenderSettings settings;
  std::vector<Framebuffer>* outputs = nullptr;
};

// One device's frame, measured inside the device from the moment it started the frame.
struct DeviceReport {
  double time_ms = 0;  // start of frame to last item finished (includes emulated idle)
  double busy_ms = 0;  // time spent rendering
  // Time the device's rendering threads were runnable but not running (their wall time
  // minus their CPU time while rendering, averaged over the threads): taken by other
  // processes or the hypervisor. Only where stolen_measured (the CPU device without a
  // quota; a driver's threads are out of sight, and a quota's throttling is the
  // device's emulated speed, not theft).
  double stolen_ms = 0;
  bool stolen_measured = false;
  uint64_t samples = 0, rays = 0, pixels = 0;
  std::vector<ItemReport> items;  // in the order rendered
  bool failed = false;
  std::string error;  // set when failed
  // Filled in by the engine for its frame record.
  bool alive = true;         // false once the device failed and was dropped
  bool rested = false;       // left out of the frame by its plan: not started at all
  double work_share = 0;     // fraction of the frame's samples this device rendered
  double planned_share = 0;  // the share the balancer intended
  // A worker rank (device/remote): each of its own devices' time in this frame, measured
  // there (Harada's deviation is over these); empty for a device that is not a rank.
  std::vector<double> local_ms;
  // A worker rank: the bytes of its result messages this frame, as they travelled
  // (compressed with --result-encoding *+zstd); 0 for a device that is not a rank.
  uint64_t result_bytes = 0;

  // Adds one finished item.
  void add(const ItemReport& r, uint64_t rays_of_item);
};

class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceInfo& info() const = 0;
  // Pulls items from `source` as device `index` until it is empty, renders them into
  // job.outputs and reports. Must not throw for rendering faults: it returns a report
  // with failed = true instead (items it pulled but did not finish are re-rendered by the
  // engine).
  virtual DeviceReport render(const FrameJob& job, WorkSource& source, int index) = 0;
  // Changes the emulated speed (for --perturb); 1 = full speed.
  virtual void set_emulated_speed(double speed) = 0;
};

// Emulates a device `speed` (< 1) times as fast as this one by idling: after each item it
// sleeps until frame start + (busy time so far) / speed. Sleeping to an absolute deadline
// keeps the scheduler's wake-up overshoot from adding up over many small items, which
// would otherwise penalise balancers that hand out many items. Emulation only: real
// slowness comes from quotas. Create one per frame, when the device starts it.
//
// "Busy" is the item's wall time, or, when the device can give it, the CPU time its one
// thread spent on it: then time the thread was preempted by other processes is not
// multiplied by 1/speed (at speed 0.1 a 10-ms preemption would otherwise cost 100 ms),
// so many emulated devices sharing a few cores keep their speeds.
// Adds the calling thread's wall time minus its CPU time over this object's life to
// `*stolen_ns` (nothing when null): time the thread was runnable but did not run.
class ThreadTimes {
 public:
  explicit ThreadTimes(std::atomic<int64_t>* stolen_ns);
  ~ThreadTimes();
  ThreadTimes(const ThreadTimes&) = delete;
  ThreadTimes& operator=(const ThreadTimes&) = delete;

 private:
  std::atomic<int64_t>* stolen_ns_;
  int64_t wall_ns_ = 0, cpu_ns_ = 0;
};

class SlowdownEmulator {
 public:
  explicit SlowdownEmulator(double speed);
  // Call after each item with its busy (rendering) time.
  void after_unit(double busy_ms);
  // The CPU time (ms) the calling thread has used so far (CLOCK_THREAD_CPUTIME_ID).
  static double thread_cpu_ms();

 private:
  double speed_;
  double busy_total_ms_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace multiray
