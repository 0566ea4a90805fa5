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

// Splits `total_ms` over items in proportion to `weights` (their samples); by equal
// shares when every weight is 0.
std::vector<double> apportion(double total_ms, const std::vector<double>& weights) {
  double sum = 0;
  for (double w : weights) sum += w;
  std::vector<double> out(weights.size());
  for (size_t k = 0; k < weights.size(); ++k)
    out[k] = sum > 0 ? total_ms * weights[k] / sum : total_ms / double(weights.size());
  return out;
}

}  // namespace

struct OpenClDevice::Impl {
  OpenClDeviceOptions opts;
  std::unique_ptr<ClRuntime> runtime;
  // The kernels that accept the scene, by RenderSettings::kernel name.
  std::map<std::string, std::unique_ptr<ClKernelRunner>> kernels;
  std::atomic<double> speed{1.0};
  int units_done = 0;  // over the device's lifetime, for fail_after

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
  // How many items to take after `first` for its batch: up to opts.batch in all, no more
  // than one launch holds if the others are as large as `first` (a batch is then about one
  // launch of work, so what the device holds back from stealing stays as today's one
  // large item), and none past fail_after.
  size_t batch_more(const WorkItem& first) const {
    const size_t capacity = size_t(runtime->tile) * size_t(runtime->tile);
    const size_t area = size_t(std::max<int64_t>(1, first.rect.area()));
    size_t items = std::min(size_t(std::max(1, opts.batch)), std::max<size_t>(1, capacity / area));
    if (opts.fail_after >= 0)
      items = std::min(items, size_t(std::max(1, opts.fail_after - units_done)));
    return items - 1;
  }
  // Renders `ids` (taken in one go) as batches of consecutive items of one view, one
  // render_rects call each, and reports one ItemReport per item.
  void render_batches(const FrameJob& job, WorkSource& source, ClKernelRunner& kernel,
                      const std::vector<uint32_t>& ids, SlowdownEmulator& slowdown,
                      DeviceReport& report) {
    for (size_t begin = 0, end; begin < ids.size(); begin = end) {
      const int view = source.item(ids[begin]).view;
      std::vector<Rect> rects;
      for (end = begin; end < ids.size() && source.item(ids[end]).view == view; ++end)
        rects.push_back(source.item(ids[end]).rect);
      const Stopwatch clock;
      const std::vector<KernelStats> ks = kernel.render_rects(
          job.views.at(size_t(view)), job.settings, rects, job.outputs->at(size_t(view)));
      const double busy = clock.elapsed_ms();
      slowdown.after_unit(busy);
      const double time = clock.elapsed_ms();
      // One launch rendered the whole batch, so no item has a time of its own: the batch's
      // time (and busy time) is split over its items in proportion to their samples, the
      // work the balancers learn a device's speed from. With batch=1 this is the item's
      // own time.
      std::vector<double> weights;
      for (const KernelStats& k : ks) weights.push_back(double(k.samples));
      const std::vector<double> times = apportion(time, weights), busys = apportion(busy, weights);
      for (size_t k = 0; k < rects.size(); ++k) {
        const uint32_t id = ids[begin + k];
        report.add(ItemReport{source.item(id), times[k], double(ks[k].samples), busys[k], id},
                   ks[k].rays);
        ++units_done;
      }
    }
  }
  static std::string kernel_names() {
    std::string names;
    for (const ClKernelEntry& e : opencl_kernels()) names += (names.empty() ? "" : ", ") + e.name;
    return names;
  }
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
    : impl_(std::make_unique<Impl>()) {
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
  impl_->speed = opts.speed;
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
  info_.emulated_speed = opts.speed;
  info_.name = "opencl " + std::to_string(opts.index) + " (" + name;
  if (!opts.cores.empty()) {
    info_.name += ", cores";
    // Appended in two steps: GCC 12 warns (-Wrestrict, falsely) on " " + to_string(c).
    for (int c : opts.cores) info_.name.append(" ").append(std::to_string(c));
  }
  if (opts.speed < 1) info_.name += ", emulated speed " + std::to_string(opts.speed).substr(0, 4);
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

void OpenClDevice::set_emulated_speed(double speed) {
  impl_->speed = speed;
  info_.emulated_speed = speed;
}

DeviceReport OpenClDevice::render(const FrameJob& job, WorkSource& source, int index) {
  DeviceReport report;
  // Pin the calling thread once per thread and device, as the CPU device does (the engine
  // keeps one thread per device); the set-up is not part of the frame time.
  thread_local const void* pinned_for = nullptr;
  if (pinned_for != this) {
    pin_current_thread(impl_->opts.cores);
    pinned_for = this;
  }
  const Stopwatch frame_clock;
  // Refuse, before taking any work, what the kernel does not implement: the engine then
  // drops this device and the others render the frame.
  std::string unsupported;
  for (const ViewSetup& v : job.views)
    if (v.foveation) unsupported = unsupported_job(info_, job.settings.kernel, "foveated");
  if (unsupported.empty()) unsupported = unsupported_job(info_, job.settings.kernel, "uniform");
  if (!unsupported.empty()) {
    report.failed = true;
    report.error = unsupported;
    report.time_ms = frame_clock.elapsed_ms();
    return report;
  }
  try {
    SlowdownEmulator slowdown(impl_->speed.load());
    ClKernelRunner& kernel = impl_->kernel(job.settings.kernel);
    std::vector<uint32_t> ids;
    for (uint32_t id; source.next(index, id);) {
      if (impl_->opts.fail_after >= 0 && impl_->units_done >= impl_->opts.fail_after) {
        report.failed = true;
        report.error = "injected failure after " + std::to_string(impl_->units_done) +
                       " units (fail_after, a testing aid)";
        break;
      }
      ids.assign(1, id);
      // Only items already this device's own (its assigned list, or shared items the
      // dispatcher moved to it) join a batch: the shared queue's and other devices' items
      // are taken one at a time, so a dynamic balancer's tail stays fine-grained and
      // stealable (batching those made queue and hybrid 4-10% slower on CPU + PoCL).
      const size_t more = std::min(impl_->batch_more(source.item(id)), source.pending(index));
      if (more > 0) source.next(index, more, ids);
      impl_->render_batches(job, source, kernel, ids, slowdown, report);
    }
  } catch (const cl::Error& e) {
    report.failed = true;
    report.error = info_.name + ": " + cl_util::describe(e);
  } catch (const std::exception& e) {
    report.failed = true;
    report.error = info_.name + ": " + e.what();
  }
  report.time_ms = frame_clock.elapsed_ms();
  return report;
}

}  // namespace multiray
