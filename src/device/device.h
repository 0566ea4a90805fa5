// The Device interface: anything that renders work units of a frame and reports, from
// inside, how long it took. Backends live in sub-folders (cpu/, later opencl/, remote/);
// the engine sees only this header.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/rect.h"
#include "render/path_tracer.h"

namespace multiray {

struct DeviceInfo {
  std::string type;  // "cpu", "opencl", ...
  std::string name;  // human readable, e.g. "cpu (1 thread, cores 0)"
  std::string spec;  // the --devices string that creates this device
  int threads = 1;
  double emulated_speed = 1.0;  // < 1: the device idles to mimic slower hardware (emulated)
  double cpu_quota = 0.0;       // > 0: real throttling by a cgroup CPU quota (fraction of a core)
};

// One piece of work: a rectangle of one view. `id` is the engine's, echoed in reports.
struct WorkUnit {
  PixelRect rect;
  uint32_t view = 0;
  uint32_t id = 0;
};

// Where a device gets its work during a frame. Implementations are thread-safe: all
// devices pull concurrently. next() returns false when nothing is left for `device`.
class WorkSource {
 public:
  virtual ~WorkSource() = default;
  virtual bool next(int device, WorkUnit& out) = 0;
};

// Everything a device needs to render one frame: the views (cameras, sizes), the settings
// and where the pixels go. outputs[v] is view v's full-size image; devices write only the
// pixels of the units they pulled.
struct FrameJob {
  std::vector<ViewSetup> views;
  RenderSettings settings;
  std::vector<Framebuffer>* outputs = nullptr;
};

struct UnitReport {
  WorkUnit unit;
  double time_ms = 0;  // busy + emulated idle for this unit
  double busy_ms = 0;  // rendering only
  uint64_t samples = 0;
};

// Measured inside the device, from the moment it started the frame.
struct DeviceReport {
  double wall_ms = 0;  // start of frame to last unit finished (includes emulated idle)
  double busy_ms = 0;  // time spent rendering
  uint64_t samples = 0, rays = 0, pixels = 0;
  std::vector<UnitReport> units;
  bool failed = false;
  std::string error;  // set when failed
};

class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceInfo& info() const = 0;
  // Pulls units from `source` as device `index` until it is empty, renders them into
  // job.outputs and reports. Must not throw for rendering faults: it returns a report
  // with failed = true instead (units it pulled but did not finish are listed as not done
  // by the engine).
  virtual DeviceReport render(const FrameJob& job, WorkSource& source, int index) = 0;
  // Changes the emulated speed (for --perturb); 1 = full speed.
  virtual void set_emulated_speed(double speed) = 0;
};

// Emulates a device `speed` (< 1) times as fast as this one by idling: after each unit it
// sleeps until frame start + (busy time so far) / speed. Sleeping to an absolute deadline
// keeps the scheduler's wake-up overshoot from adding up over many small units, which
// would otherwise penalise balancers that hand out many units. Emulation only: real
// slowness comes from quotas. Create one per frame, when the device starts it.
class SlowdownEmulator {
 public:
  explicit SlowdownEmulator(double speed);
  // Call after each unit with its busy (rendering) time.
  void after_unit(double busy_ms);

 private:
  double speed_;
  double busy_total_ms_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace multiray
