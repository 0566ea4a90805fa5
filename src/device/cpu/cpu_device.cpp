#include "device/cpu/cpu_device.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
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
#include "device/cpu/item_time_share.h"
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
  std::atomic<double> speed{1.0};
  std::atomic<int> items_done{0};  // over the device's lifetime, for fail_after
};

CpuDevice::CpuDevice(SceneCache& scenes, CpuDeviceOptions opts, std::string spec) {
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
  impl_->speed = opts.speed;
  info_.type = "cpu";
  info_.spec = std::move(spec);
  info_.threads = opts.threads;
  info_.emulated_speed = opts.speed;
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
  if (opts.speed < 1) info_.name += ", emulated speed " + std::to_string(opts.speed).substr(0, 4);
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
  return caps;
}

uint64_t CpuDevice::arena_entries() const { return impl_->arena_entries; }
int CpuDevice::item_takers() const { return impl_->takers; }

void CpuDevice::set_emulated_speed(double speed) {
  impl_->speed = speed;
  info_.emulated_speed = speed;
}

// One frame of one device, shared by the threads that render it.
struct CpuDevice::Frame {
  Frame(const FrameJob& j, const Kernel& k, WorkSource& s, int i, DeviceReport& r)
      : job(j), kernel(k), source(s), index(i), report(r) {}
  const FrameJob& job;
  const Kernel& kernel;
  WorkSource& source;
  int index;
  DeviceReport& report;
  std::atomic<int64_t> stolen_ns{0};  // multi-threaded: summed over the arena's threads
  // Team mode only:
  std::mutex mutex;               // guards `report`
  ItemTimeShare share;            // the items' times (ItemReport::time_ms)
  std::atomic<bool> stop{false};  // a thread failed: the others take no more items
  std::atomic<int> takers{0};     // team loops that took at least one item
};

DeviceReport CpuDevice::render(const FrameJob& job, WorkSource& source, int index) {
  DeviceReport report;
  // Pin the calling thread and move it into the quota group once per thread and device
  // (the engine keeps one thread per device); this set-up is not part of the frame time.
  thread_local const void* prepared_for = nullptr;
  if (prepared_for != this) {
    impl_->setup->prepare_current_thread();
    prepared_for = this;
  }
  const Stopwatch frame_clock;
  ++impl_->render_calls;
  // Stolen time (DeviceReport::stolen_ms): with one thread, per item on this thread; with
  // several, per chunk on each arena thread, averaged over the threads. A quota's
  // throttling is this device's emulated speed, and foveated units are not measured.
  const bool one_thread = impl_->opts.threads == 1;
  report.stolen_measured = !impl_->quota;
  try {
    Frame f(job, impl_->kernel(job.settings.kernel), source, index, report);
    // Threads take items themselves unless the frame needs items one at a time: the
    // emulated speed idles after each item, and foveated units share the device's
    // sample buffers.
    bool team = !one_thread && impl_->speed.load() >= 1.0;
    for (const ViewSetup& v : job.views) team = team && !v.foveation;
    // The arena is entered once a frame, not once an item: entering and leaving it per
    // item let its threads fall asleep between items, to be woken for the next.
    ++impl_->arena_entries;
    impl_->arena.execute([&] {
      try {
        team ? render_team(f) : render_in_turn(f);
      } catch (const std::exception& e) {
        report.failed = true;
        report.error = e.what();
      }
    });
    impl_->takers = team ? f.takers.load() : 1;
    if (!one_thread) report.stolen_ms = double(f.stolen_ns.load()) * 1e-6 / impl_->opts.threads;
  } catch (const std::exception& e) {
    report.failed = true;
    report.error = e.what();
  }
  report.time_ms = frame_clock.elapsed_ms();
  return report;
}

void CpuDevice::count_item() {
  const int done = impl_->items_done.fetch_add(1);
  if (impl_->opts.fail_after >= 0 && done >= impl_->opts.fail_after)
    throw std::runtime_error("injected failure after " + std::to_string(done) +
                             " items (fail_after, a testing aid)");
}

void CpuDevice::render_rect(Frame& f, const ViewSetup& view, Rect r, Framebuffer& out,
                            std::atomic<uint64_t>& samples, std::atomic<uint64_t>& rays) {
  std::atomic<int64_t>* stolen = impl_->opts.threads == 1 ? nullptr : &f.stolen_ns;
  const auto chunk = [&](Rect sub) {
    const ThreadTimes times(stolen);
    const KernelStats ks = f.kernel.render_rect(view, f.job.settings, sub, out);
    samples += ks.samples;
    rays += ks.rays;
  };
  const int tile = std::max(1, impl_->opts.tile);
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

// Items one at a time, each cut into tiles for the arena's threads (the caller's thread
// takes them). Runs inside the arena.
void CpuDevice::render_in_turn(Frame& f) {
  const bool one_thread = impl_->opts.threads == 1;
  SlowdownEmulator slowdown(impl_->speed.load());
  for (uint32_t id; f.source.next(f.index, id);) {
    count_item();
    const Stopwatch item_clock;
    // With one thread the item runs on this thread: its CPU time is the device's own
    // work (see SlowdownEmulator).
    const double cpu_start = one_thread ? SlowdownEmulator::thread_cpu_ms() : 0;
    const WorkItem& item = f.source.item(id);
    const ViewSetup& view = f.job.views.at(size_t(item.view));
    Framebuffer& out = f.job.outputs->at(size_t(item.view));
    std::atomic<uint64_t> samples{0}, rays{0};
    if (view.foveation) {
      f.report.stolen_measured &= one_thread;
      render_foveated(f.job, f.kernel, view, item.rect, out, samples, rays);
    } else {
      render_rect(f, view, item.rect, out, samples, rays);
    }
    const double busy = item_clock.elapsed_ms();
    const double cpu = one_thread ? SlowdownEmulator::thread_cpu_ms() - cpu_start : busy;
    if (one_thread) f.report.stolen_ms += std::max(0.0, busy - cpu);
    slowdown.after_unit(cpu);
    f.report.add(ItemReport{item, item_clock.elapsed_ms(), double(samples.load()), busy, id},
                 rays);
  }
}

// Every arena thread takes items itself until none is left: no hand-over between items.
// An item of several tiles is still cut, its tiles open to threads that ran out of items.
void CpuDevice::render_team(Frame& f) {
  const auto loop = [this, &f] {
    int taken = 0;
    try {
      for (uint32_t id; !f.stop && f.source.next(f.index, id);) {
        if (taken++ == 0) ++f.takers;
        count_item();
        const WorkItem& item = f.source.item(id);
        const ViewSetup& view = f.job.views.at(size_t(item.view));
        std::atomic<uint64_t> samples{0}, rays{0};
        const double mark = f.share.start();
        try {
          render_rect(f, view, item.rect, f.job.outputs->at(size_t(item.view)), samples, rays);
        } catch (...) {
          f.share.finish(mark);
          throw;
        }
        const double ms = f.share.finish(mark);
        const std::lock_guard<std::mutex> lock(f.mutex);
        f.report.add(ItemReport{item, ms, double(samples.load()), ms, id}, rays);
      }
    } catch (const std::exception& e) {
      const std::lock_guard<std::mutex> lock(f.mutex);
      if (!f.report.failed) f.report.error = e.what();
      f.report.failed = true;
      f.stop = true;
    }
  };
  oneapi::tbb::task_group team;
  for (int t = 1; t < impl_->opts.threads; ++t) team.run(loop);
  loop();  // the caller's thread is one of the team
  team.wait();
}

void CpuDevice::render_foveated(const FrameJob& job, const Kernel& kernel, const ViewSetup& view,
                                Rect r, Framebuffer& out, std::atomic<uint64_t>& samples,
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
  if (impl_->sample_values.size() < f.size()) {
    impl_->sample_values.resize(f.size());
    impl_->sample_stamp.resize(f.size(), 0);
  }
  const uint64_t stamp = impl_->render_calls << 32 | view.view;
  std::vector<uint32_t> idx = select_samples(f, r);
  idx.erase(std::remove_if(idx.begin(), idx.end(),
                           [&](uint32_t s) {
                             if (impl_->sample_stamp[s] == stamp) return true;
                             impl_->sample_stamp[s] = stamp;
                             return false;
                           }),
            idx.end());
  Vec3* values = impl_->sample_values.data();
  const int tile = std::max(1, impl_->opts.tile);
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<size_t>(0, idx.size(), 64),
                            [&](const oneapi::tbb::blocked_range<size_t>& b) {
                              const KernelStats ks = FoveatedKernel(kernel).shade(
                                  view, job.settings, idx.data() + b.begin(), b.size(), values);
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
