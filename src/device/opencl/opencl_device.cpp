#include "device/opencl/opencl_device.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <stdexcept>
#include <thread>

#include "core/clock.h"
#include "core/error.h"
#include "device/opencl/cl_runtime.h"
#include "device/opencl/opencl_kernels.h"
#include "device/scene_memory.h"

namespace multiray {

namespace {

void pin_current_thread(const std::vector<int>& cores) {
  if (cores.empty()) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cores) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

}  // namespace

struct OpenClDevice::Impl {
  OpenClDeviceOptions opts;
  std::unique_ptr<ClRuntime> runtime;
  // The kernels that accept the scene, by RenderSettings::kernel name.
  std::map<std::string, std::unique_ptr<ClKernelRunner>> kernels;

  // Builds the kernels whose registry entry accepts the cache's scene (opencl_kernels.h),
  // as the CPU device builds those of cpu_kernels().
  void setup(const cl::Device& device, SceneCache& scenes) {
    runtime = std::make_unique<ClRuntime>(device, opts.index, opts.tile, opts.work_group);
    for (const ClKernelEntry& e : opencl_kernels())
      if (e.accepts(scenes.scene()))
        kernels.emplace(e.name, e.make(*runtime, scenes, opts.compact));
    if (kernels.empty())
      throw DeviceError("opencl device " + std::to_string(opts.index) +
                        ": no OpenCL kernel renders this scene (it has no triangles and no "
                        "volume)");
  }
  // Throws std::invalid_argument, in one line, for a kernel this device did not build.
  ClKernelRunner& kernel(const std::string& name) {
    const auto it = kernels.find(name);
    if (it != kernels.end()) return *it->second;
    if (!find_opencl_kernel(name))
      throw std::invalid_argument("opencl device has no kernel '" + name + "' (it has " +
                                  kernel_names() + ")");
    throw std::invalid_argument("opencl device has no kernel '" + name + "' for this scene");
  }
  static std::string kernel_names() {
    std::string names;
    for (const ClKernelEntry& e : opencl_kernels()) names += (names.empty() ? "" : ", ") + e.name;
    return names;
  }
};

// One frame's batches for the device loop: up to `batch` items of one view in one
// render_rects call (a launch). The loop splits a batch's time over its items by samples.
class OpenClDevice::Batches : public BatchRenderer {
 public:
  Batches(const Impl& impl, const FrameJob& job, ClKernelRunner& kernel, const std::string& name)
      : impl_(impl), job_(job), kernel_(kernel), name_(name) {}

  // Up to opts.batch items, no more than one launch holds if the others are as large as
  // `first`: a batch is then about one launch of work, so what the device holds back from
  // stealing stays as one large item would.
  size_t batch_limit(const WorkItem& first) const override {
    const size_t capacity = size_t(impl_.runtime->tile) * size_t(impl_.runtime->tile);
    const size_t area = size_t(std::max<int64_t>(1, first.rect.area()));
    return std::min(size_t(std::max(1, impl_.opts.batch)), std::max<size_t>(1, capacity / area));
  }

  // Errors say which device: "<name>: <OpenCL error>".
  std::vector<KernelStats> render(const std::vector<WorkItem>& items) override {
    const size_t view = size_t(items.front().view);
    std::vector<Rect> rects;
    for (const WorkItem& item : items) rects.push_back(item.rect);
    try {
      return kernel_.render_rects(job_.views.at(view), job_.settings, rects,
                                  job_.outputs->at(view));
    } catch (const cl::Error& e) {
      throw std::runtime_error(name_ + ": " + cl_util::describe(e));
    } catch (const std::exception& e) {
      throw std::runtime_error(name_ + ": " + e.what());
    }
  }

 private:
  const Impl& impl_;
  const FrameJob& job_;
  ClKernelRunner& kernel_;
  const std::string& name_;
};

DeviceCapabilities OpenClDevice::capabilities() {
  DeviceCapabilities caps;
  bool point_samples = false;
  for (const ClKernelEntry& e : opencl_kernels()) {
    caps.kernels.push_back(e.name);
    point_samples = point_samples || e.point_samples;
  }
  caps.sampling = sampling_modes(point_samples);  // sample maps; no foveation
  // A device's own info() names the one it built.
  caps.representation = "opencl-flat-bvh, opencl-compact or opencl-volume";
  return caps;
}

OpenClDevice::OpenClDevice(SceneCache& scenes, OpenClDeviceOptions opts, std::string spec)
    : LoopDevice({opts.speed, opts.fail_after}), impl_(std::make_unique<Impl>()) {
  if (!(opts.speed > 0 && opts.speed <= 1))
    throw InputError("opencl device: speed must be in (0, 1], got " + std::to_string(opts.speed));
  if (opts.tile < 1 || opts.tile > 4096)
    throw InputError("opencl device: tile must be in 1..4096");
  if (opts.work_group < 1 || opts.work_group > 4096)
    throw InputError("opencl device: wg must be in 1..4096");
  if (opts.batch < 1 || opts.batch > MR_BATCH_MAX)
    throw InputError("opencl device: batch must be in 1.." + std::to_string(MR_BATCH_MAX));
  const int ncpu = int(std::thread::hardware_concurrency());
  for (int c : opts.cores)
    if (c < 0 || (ncpu > 0 && c >= ncpu))
      throw InputError("opencl device: core " + std::to_string(c) + " does not exist");
  const std::vector<cl::Device> all = cl_util::all_devices();
  if (all.empty())
    throw InputError(
        "opencl device: no OpenCL device found (is an ICD such as pocl-opencl-icd "
        "installed? `multiray devices` lists what is found)");
  if (opts.index < 0 || size_t(opts.index) >= all.size())
    throw InputError("opencl device: there is no OpenCL device " + std::to_string(opts.index) +
                     " (found " + std::to_string(all.size()) +
                     ", numbered from 0; see `multiray devices`)");
  check_scene_fits(scenes.scene(), opts.compact, opts.memory_limit, "--devices '" + spec + "'");
  impl_->opts = opts;
  const cl::Device& device = all[size_t(opts.index)];
  std::string name = "?";
  try {
    name = device.getInfo<CL_DEVICE_NAME>();
    info_.threads = int(device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
    impl_->setup(device, scenes);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl device " + std::to_string(opts.index) + " (" + name +
                      "): setting up failed: " + cl_util::describe(e));
  }
  info_.type = "opencl";
  info_.caps = capabilities();
  info_.caps.kernels.clear();  // what this device built for its scene
  for (const auto& [kernel, runner] : impl_->kernels) info_.caps.kernels.push_back(kernel);
  info_.caps.representation = impl_->kernels.count("volume") ? "opencl-volume"
                              : opts.compact                 ? "opencl-compact"
                                                             : "opencl-flat-bvh";
  for (const auto& [kernel, runner] : impl_->kernels) {
    info_.scene_bytes += runner->scene_bytes;
    // The default size is fitted silently; one asked for is fitted too, never refused
    // (a size changes no pixel), and the user told.
    if (opts.work_group_given && runner->work_group < size_t(opts.work_group))
      info_.notes.push_back(spec + ": wg=" + std::to_string(opts.work_group) +
                            " is more than the " + kernel + " kernel allows on '" + name +
                            "'; it uses wg=" + std::to_string(runner->work_group));
  }
  if (impl_->kernels.count("path"))
    info_.representation = opts.compact ? "opencl-compact" : "opencl-flat-bvh";
  // llvmpipe (Mesa's software driver, under rusticl) ends a work-item's loops after 65535
  // iterations of all its loops together (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS): pixels of
  // many samples times bounces come out wrong, silently (docs/devices.md).
  if (name.find("llvmpipe") != std::string::npos)
    info_.notes.push_back(spec +
                          ": llvmpipe stops a work-item after 65535 loop iterations, so "
                          "pixels of many samples or bounces come out too dark");
  info_.memory_limit = opts.memory_limit;
  info_.spec = std::move(spec);
  info_.name = "opencl " + std::to_string(opts.index) + " (" + name;
  if (!opts.cores.empty()) {
    info_.name += ", cores";
    // Appended in two steps: GCC 12 warns (-Wrestrict, falsely) on " " + to_string(c).
    for (int c : opts.cores) info_.name.append(" ").append(std::to_string(c));
  }
  info_.name += emulated_label(opts.speed);
  if (opts.compact) info_.name += ", compact scene";
  if (opts.memory_limit > 0) info_.name += ", emulated memory " + format_bytes(opts.memory_limit);
  info_.name += ")";
}

OpenClDevice::~OpenClDevice() = default;

bool OpenClDevice::kernel_from_cache() const {
  for (const auto& [kernel, runner] : impl_->kernels)
    if (!runner->from_cache) return false;
  return true;
}
size_t OpenClDevice::work_group_size(const std::string& kernel) const {
  const auto it = impl_->kernels.find(kernel);
  return it == impl_->kernels.end() ? 0 : it->second->work_group;
}
size_t OpenClDevice::work_group_limit(const std::string& kernel) const {
  const auto it = impl_->kernels.find(kernel);
  return it == impl_->kernels.end() ? 0 : it->second->work_group_limit;
}

DeviceReport OpenClDevice::render(const FrameJob& job, WorkSource& source, int index) {
  // Pin the calling thread once per thread and device, as the CPU device does (the engine
  // keeps one thread per device); the set-up is not part of the frame time.
  thread_local const void* pinned_for = nullptr;
  if (pinned_for != this) {
    pin_current_thread(impl_->opts.cores);
    pinned_for = this;
  }
  // The driver renders: the calling thread's CPU time is not the work (FrameMode).
  FrameLoop frame(loop_, info_, job, source, index, FrameMode{});
  if (frame.refused()) return frame.finish();
  try {
    Batches batches(*impl_, job, impl_->kernel(job.settings.kernel), info_.name);
    frame.run(batches);
  } catch (const std::exception& e) {
    frame.fail(info_.name + ": " + e.what());
  }
  return frame.finish();
}

}  // namespace multiray
