#include "device/device_loop.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace multiray {

size_t BatchRenderer::batch_limit(const WorkItem& /*first*/) const { return 1; }

DeviceLoop::DeviceLoop(LoopOptions options)
    : fail_after_(options.fail_after), speed_(options.speed) {}

std::string emulated_label(double speed) {
  return speed < 1 ? ", emulated speed " + std::to_string(speed).substr(0, 4) : "";
}

std::vector<double> apportion(double total_ms, const std::vector<double>& weights) {
  double sum = 0;
  for (double w : weights) sum += w;
  std::vector<double> out(weights.size());
  for (size_t k = 0; k < weights.size(); ++k)
    out[k] = sum > 0 ? total_ms * weights[k] / sum : total_ms / double(weights.size());
  return out;
}

namespace {

// Empty when `info` can render `job`: its kernel with the sampling of its views.
std::string unsupported_frame(const DeviceInfo& info, const FrameJob& job) {
  for (const ViewSetup& v : job.views)
    if (v.foveation) return unsupported_job(info, job.settings.kernel, "foveated");
  return unsupported_job(info, job.settings.kernel, "uniform");
}

}  // namespace

FrameLoop::FrameLoop(DeviceLoop& device, const DeviceInfo& info, const FrameJob& job,
                     WorkSource& source, int index, FrameMode mode)
    : device_(device), job_(job), source_(source), index_(index), mode_(mode) {
  if (const std::string why = unsupported_frame(info, job); !why.empty()) fail(why);
}

void FrameLoop::fail(const std::string& error) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!report_.failed) report_.error = error;  // the first fault is the cause
  report_.failed = true;
  stop_ = true;
}

DeviceReport FrameLoop::finish() {
  report_.time_ms = clock_.elapsed_ms();
  return std::move(report_);
}

void FrameLoop::take(BatchRenderer& renderer, uint32_t first, std::vector<uint32_t>& ids) {
  // The item was pulled before the check, as a device that breaks mid-frame would have:
  // the engine re-renders it.
  const int fail_after = device_.fail_after_;
  const int done = device_.taken_.fetch_add(1);
  // The message names fail_after, not `done`: on a device of several threads, two takes
  // past the limit race to report first, and the count each saw differs.
  if (fail_after >= 0 && done >= fail_after)
    throw std::runtime_error("injected failure after " + std::to_string(fail_after) +
                             " items (fail_after, a testing aid)");
  ids.assign(1, first);
  size_t more = std::max<size_t>(1, renderer.batch_limit(source_.item(first))) - 1;
  if (more == 0) return;
  // (With concurrent threads each batching, another thread's take between the count
  // above and this one could pass fail_after; no backend batches concurrently.)
  if (fail_after >= 0) more = std::min(more, size_t(std::max(0, fail_after - done - 1)));
  // Only items already this device's own (its assigned list, or shared items the
  // dispatcher moved to it) join a batch: the shared queue's and other devices' items are
  // taken one at a time, so a dynamic balancer's tail stays fine-grained and stealable
  // (batching those made queue and hybrid 4-10% slower on CPU + PoCL).
  more = std::min(more, source_.pending(index_));
  if (more > 0) device_.taken_ += int(source_.next(index_, more, ids));
}

void FrameLoop::run(BatchRenderer& renderer) {
  // The emulated idle follows batches one after another (FrameMode::concurrent needs
  // speed 1); it sleeps to frame start + busy / speed, measured from here.
  std::optional<SlowdownEmulator> slowdown;
  if (!mode_.concurrent) slowdown.emplace(device_.speed());
  bool took = false;
  try {
    std::vector<uint32_t> ids;
    for (uint32_t id; !stop_ && source_.next(index_, id);) {
      if (!took) ++takers_, took = true;
      take(renderer, id, ids);
      // Consecutive items of one view make one batch.
      for (size_t begin = 0, end; begin < ids.size(); begin = end) {
        const int view = source_.item(ids[begin]).view;
        for (end = begin + 1; end < ids.size() && source_.item(ids[end]).view == view;) ++end;
        render_batch(renderer, ids, begin, end, slowdown ? &*slowdown : nullptr);
      }
    }
  } catch (const std::exception& e) {
    fail(e.what());
  }
}

void FrameLoop::render_batch(BatchRenderer& renderer, const std::vector<uint32_t>& ids,
                             size_t begin, size_t end, SlowdownEmulator* slowdown) {
  std::vector<WorkItem> items;
  for (size_t k = begin; k < end; ++k) items.push_back(source_.item(ids[k]));
  const double mark = mode_.concurrent ? share_.start() : 0;
  const Stopwatch clock;
  const double cpu_start = mode_.on_calling_thread ? SlowdownEmulator::thread_cpu_ms() : 0;
  std::vector<KernelStats> stats;
  try {
    stats = renderer.render(items);
  } catch (...) {
    if (mode_.concurrent) share_.finish(mark);  // every start() needs its finish()
    throw;
  }
  if (stats.size() != items.size())
    throw std::logic_error("a backend returned stats for " + std::to_string(stats.size()) +
                           " of " + std::to_string(items.size()) + " items");
  double busy = clock.elapsed_ms(), time = busy, stolen = 0;
  if (mode_.concurrent) {
    time = busy = share_.finish(mark);
  } else {
    const double cpu =
        mode_.on_calling_thread ? SlowdownEmulator::thread_cpu_ms() - cpu_start : busy;
    if (mode_.on_calling_thread) stolen = std::max(0.0, busy - cpu);
    if (slowdown) slowdown->after_unit(cpu);
    time = clock.elapsed_ms();  // the item's time holds its emulated idle
  }
  // One call rendered the whole batch, so no item has a time of its own: the batch's time
  // (and busy time) is split over its items in proportion to their samples, the work the
  // balancers learn a device's speed from. An item alone keeps its own time.
  std::vector<double> times{time}, busys{busy};
  if (items.size() > 1) {
    std::vector<double> weights;
    for (const KernelStats& k : stats) weights.push_back(double(k.samples));
    times = apportion(time, weights), busys = apportion(busy, weights);
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  report_.stolen_ms += stolen;
  for (size_t k = 0; k < items.size(); ++k)
    report_.add(ItemReport{items[k], times[k], double(stats[k].samples), busys[k], ids[begin + k]},
                stats[k].rays);
}

}  // namespace multiray
