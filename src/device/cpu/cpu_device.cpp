#include "device/cpu/cpu_device.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>

#include <oneapi/tbb/blocked_range2d.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include "core/clock.h"
#include "core/error.h"
#include "device/cpu/cgroup_quota.h"
#include "device/cpu/thread_setup.h"
#include "device/scene_memory.h"
#include "render/foveated.h"
#include "render/kernel.h"

namespace multiray {

struct CpuDevice::Impl {
  // Builds every CPU kernel that can render the cache's scene (each from the
  // representation it needs, shared with the other devices through the cache).
  Impl(SceneCache& scenes, const CpuDeviceOptions& o, const std::string& name)
      : opts(o), arena(o.threads, 1) {
    for (const KernelEntry& e : cpu_kernels())
      if (e.accepts(scenes.scene())) kernels.emplace(e.name, e.make(scenes, o.compact));
    if (o.quota > 0) quota.emplace(name, o.quota * o.threads);
    setup.emplace(arena, o.cores, quota ? &*quota : nullptr);
  }
  ~Impl() {
    setup.reset();
    // The threads that ran the arena may still be in the quota group; move out the ones we
    // can reach (the caller's), the rest leave when the process ends.
    if (quota) CgroupQuota::leave_current_thread();
  }
  // Throws std::invalid_argument for a kernel this device does not have (a failed frame).
  const Kernel& kernel(const std::string& name) const {
    const auto it = kernels.find(name);
    if (it == kernels.end())
      throw std::invalid_argument("cpu device has no kernel '" + name + "'");
    return *it->second;
  }
  std::map<std::string, std::unique_ptr<Kernel>> kernels;  // every CPU kernel, by name
  // Foveated sampling: values of the samples rendered in this render() call, and for
  // each sample the (call, view) it was last rendered for, so that a sample needed by
  // several units of one device in one frame is rendered once.
  std::vector<Vec3> sample_values;
  std::vector<uint64_t> sample_stamp;
  uint64_t render_calls = 0;
  uint64_t arena_entries = 0;  // testing aid: times render() entered `arena`
  int takers = 0;              // testing aid: threads that took items, last frame
  CpuDeviceOptions opts;
  std::optional<CgroupQuota> quota;  // declared before `setup`, which points to it
  oneapi::tbb::task_arena arena;
  std::optional<ThreadSetup> setup;
};

CpuDevice::CpuDevice(SceneCache& scenes, CpuDeviceOptions opts, std::string spec)
    : LoopDevice({opts.speed, opts.fail_after}) {
  if (opts.threads < 1 || opts.threads > 1024)
    throw InputError("cpu device: threads must be in 1..1024, got " +
                     std::to_string(opts.threads));
  const int ncpu = int(std::thread::hardware_concurrency());
  for (int c : opts.cores)
    if (c < 0 || (ncpu > 0 && c >= ncpu))
      throw InputError("cpu device: core " + std::to_string(c) +
                       " does not exist (this machine has " + std::to_string(ncpu) + ")");
  if (!(opts.speed > 0 && opts.speed <= 1))
    throw InputError("cpu device: speed must be in (0, 1], got " + std::to_string(opts.speed));
  check_scene_fits(scenes.scene(), opts.compact, opts.memory_limit, "--devices '" + spec + "'");
  static std::atomic<int> counter{0};
  impl_ = std::make_unique<Impl>(scenes, opts, "cpu" + std::to_string(counter++));
  info_.type = "cpu";
  info_.spec = std::move(spec);
  info_.threads = opts.threads;
  info_.cpu_quota = opts.quota;
  info_.caps = capabilities();
  if (scenes.scene().has_triangles()) {
    const RenderScene& rs = scenes.mesh(opts.compact);
    info_.representation = opts.compact ? "compact" : "embree";
    info_.scene_bytes = rs.bytes();
  }
  info_.memory_limit = opts.memory_limit;
  info_.name =
      "cpu (" + std::to_string(opts.threads) + (opts.threads == 1 ? " thread" : " threads");
  if (!opts.cores.empty()) {
    info_.name += ", cores";
    for (int c : opts.cores) info_.name.append(" ").append(std::to_string(c));
  }
  if (opts.quota > 0) info_.name += ", quota " + std::to_string(opts.quota).substr(0, 4);
  info_.name += emulated_label(opts.speed);
  if (opts.compact) info_.name += ", compact scene";
  if (opts.memory_limit > 0) info_.name += ", emulated memory " + format_bytes(opts.memory_limit);
  info_.name += ")";
}

CpuDevice::~CpuDevice() = default;

DeviceCapabilities CpuDevice::capabilities() {
  DeviceCapabilities caps;
  bool point_samples = false;
  for (const KernelEntry& e : cpu_kernels()) {
    caps.kernels.push_back(e.name);
    point_samples = point_samples || e.point_samples;
  }
  caps.sampling = sampling_modes(point_samples);
  caps.representation = "embree";
  caps.shadow_catcher = true;  // the path kernel's catcher plane (render/shadow_catcher.h)
  return caps;
}

uint64_t CpuDevice::arena_entries() const { return impl_->arena_entries; }
int CpuDevice::item_takers() const { return impl_->takers; }

// One frame's rendering of one item at a time for the device loop: a rect of several tiles
// is cut into tiles for the arena's threads; a foveated unit renders its samples, then its
// pixels. Runs inside the device's arena.
class CpuDevice::Items : public BatchRenderer {
 public:
  Items(Impl& impl, const FrameJob& job, const Kernel& kernel)
      : impl_(impl), job_(job), kernel_(kernel) {}

  std::vector<KernelStats> render(const std::vector<WorkItem>& items) override {
    const WorkItem& item = items.front();  // one at a time (batch_limit 1)
    const ViewSetup& view = job_.views.at(size_t(item.view));
    Framebuffer& out = job_.outputs->at(size_t(item.view));
    std::atomic<uint64_t> samples{0}, rays{0};
    if (view.foveation)
      render_foveated(view, item.rect, out, samples, rays);
    else
      render_rect(view, item.rect, out, samples, rays);
    return {KernelStats{samples.load(), rays.load()}};
  }

  // Several threads: the time their chunks were runnable but not running, summed.
  std::atomic<int64_t> stolen_ns{0};

 private:
  void render_rect(const ViewSetup& view, Rect r, Framebuffer& out, std::atomic<uint64_t>& samples,
                   std::atomic<uint64_t>& rays);
  void render_foveated(const ViewSetup& view, Rect r, Framebuffer& out,
                       std::atomic<uint64_t>& samples, std::atomic<uint64_t>& rays);

  Impl& impl_;
  const FrameJob& job_;
  const Kernel& kernel_;
};

DeviceReport CpuDevice::render(const FrameJob& job, WorkSource& source, int index) {
  // Pin the calling thread and move it into the quota group once per thread and device
  // (the engine keeps one thread per device); this set-up is not part of the frame time.
  thread_local const void* prepared_for = nullptr;
  if (prepared_for != this) {
    impl_->setup->prepare_current_thread();
    prepared_for = this;
  }
  const bool one_thread = impl_->opts.threads == 1;
  bool foveated = false;
  for (const ViewSetup& v : job.views) foveated = foveated || v.foveation;
  // Threads take items themselves unless the frame needs items one at a time: the
  // emulated speed idles after each item, and foveated units share the device's sample
  // buffers. With one thread the item runs on this thread: its CPU time is the device's
  // own work (see SlowdownEmulator).
  const bool team = !one_thread && loop_.speed() >= 1.0 && !foveated;
  FrameLoop frame(loop_, info_, job, source, index, FrameMode{team, one_thread});
  ++impl_->render_calls;
  // Stolen time (DeviceReport::stolen_ms): with one thread, per item on this thread; with
  // several, per chunk on each arena thread, averaged over the threads. A quota's
  // throttling is this device's emulated speed, and foveated units on several threads are
  // not measured.
  frame.report().stolen_measured = !impl_->quota && (one_thread || !foveated);
  if (frame.refused()) return frame.finish();
  try {
    Items items(*impl_, job, impl_->kernel(job.settings.kernel));
    // The arena is entered once a frame, not once an item: entering and leaving it per
    // item let its threads fall asleep between items, to be woken for the next.
    ++impl_->arena_entries;
    impl_->arena.execute([&] {
      if (!team) return frame.run(items);
      // Every arena thread takes items itself until none is left: no hand-over between
      // items. An item of several tiles is still cut, its tiles open to threads that ran
      // out of items.
      oneapi::tbb::task_group threads;
      for (int t = 1; t < impl_->opts.threads; ++t) threads.run([&] { frame.run(items); });
      frame.run(items);  // the caller's thread is one of the team
      threads.wait();
    });
    impl_->takers = team ? frame.takers() : 1;
    if (!one_thread)
      frame.report().stolen_ms = double(items.stolen_ns.load()) * 1e-6 / impl_->opts.threads;
  } catch (const std::exception& e) {
    frame.fail(e.what());
  }
  return frame.finish();
}

void CpuDevice::Items::render_rect(const ViewSetup& view, Rect r, Framebuffer& out,
                                   std::atomic<uint64_t>& samples, std::atomic<uint64_t>& rays) {
  std::atomic<int64_t>* stolen = impl_.opts.threads == 1 ? nullptr : &stolen_ns;
  const auto chunk = [&](Rect sub) {
    const ThreadTimes times(stolen);
    const KernelStats ks = kernel_.render_rect(view, job_.settings, sub, out);
    samples += ks.samples;
    rays += ks.rays;
  };
  const int tile = std::max(1, impl_.opts.tile);
  if (r.width() <= tile && r.height() <= tile) return chunk(r);  // one tile: no split
  // Isolated: a thread waiting for this item's tiles helps only with them, never starts
  // another team loop (which would hold this item until the frame's end).
  oneapi::tbb::this_task_arena::isolate([&] {
    oneapi::tbb::parallel_for(
        oneapi::tbb::blocked_range2d<int>(r.y0, r.y1, tile, r.x0, r.x1, tile),
        [&](const oneapi::tbb::blocked_range2d<int>& b) {
          chunk({b.cols().begin(), b.rows().begin(), b.cols().end(), b.rows().end()});
        });
  });
}

void CpuDevice::Items::render_foveated(const ViewSetup& view, Rect r, Framebuffer& out,
                                       std::atomic<uint64_t>& samples,
                                       std::atomic<uint64_t>& rays) {
  // The unit's samples are rendered once for the whole unit (not per thread tile, which
  // would render the samples on tile borders twice), then its pixels reconstructed.
  // Samples this device already rendered for an earlier unit of the frame are reused:
  // same values (same random numbers), less work when a device gets adjacent pieces.
  // The unit reports as its samples those positioned inside it (its weight in the
  // engine's pixel_weight), so balancers measure speed in the units they split by; the
  // samples rendered for the rect's border are overhead, visible in its time and rays.
  const FoveationFrame& f = foveation_of(view);
  samples += samples_in_rect(f, r);
  if (impl_.sample_values.size() < f.size()) {
    impl_.sample_values.resize(f.size());
    impl_.sample_stamp.resize(f.size(), 0);
  }
  const uint64_t stamp = impl_.render_calls << 32 | view.view;
  std::vector<uint32_t> idx = select_samples(f, r);
  idx.erase(std::remove_if(idx.begin(), idx.end(),
                           [&](uint32_t s) {
                             if (impl_.sample_stamp[s] == stamp) return true;
                             impl_.sample_stamp[s] = stamp;
                             return false;
                           }),
            idx.end());
  Vec3* values = impl_.sample_values.data();
  const int tile = std::max(1, impl_.opts.tile);
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<size_t>(0, idx.size(), 64),
                            [&](const oneapi::tbb::blocked_range<size_t>& b) {
                              const KernelStats ks = FoveatedKernel(kernel_).shade(
                                  view, job_.settings, idx.data() + b.begin(), b.size(), values);
                              rays += ks.rays;
                            });
  oneapi::tbb::parallel_for(
      oneapi::tbb::blocked_range2d<int>(r.y0, r.y1, tile, r.x0, r.x1, tile),
      [&](const oneapi::tbb::blocked_range2d<int>& b) {
        reconstruct_rect(
            f, values, {b.cols().begin(), b.rows().begin(), b.cols().end(), b.rows().end()}, out);
      });
}

}  // namespace multiray
