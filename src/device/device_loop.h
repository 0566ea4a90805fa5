// The one device loop: how every backend pulls its work, fails on purpose (`fail_after`),
// emulates a slower device (`speed`, always labelled emulated) and reports each item
// (device, rect, samples, busy and wall ms). A backend supplies only "render this batch of
// items" (BatchRenderer) and its own set-up; pulling, the injected failure, the emulated
// idle and the per-item report are written here once, so they mean the same on every
// backend (DESIGN.md: timing is measured where the work happens, inside the device).
//
// A backend's render() is then, in outline:
//
//   FrameLoop frame(loop_, info_, job, source, index, mode);   // the frame's clock starts
//   if (frame.refused()) return frame.finish();                 // e.g. a kernel it lacks
//   MyBatches batches(...);                                     // the frame's set-up
//   frame.run(batches);                                         // pull, render, report
//   return frame.finish();
//
// Remote ranks (distributed/remote_device.h) do not run this loop on the master: they ship
// items to a worker, whose local devices run it and measure each item there.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include "core/clock.h"
#include "device/device.h"
#include "device/item_time_share.h"
#include "render/render_settings.h"

namespace multiray {

// The options every backend's device takes from its --devices spec (`speed`, `fail_after`).
struct LoopOptions {
  double speed = 1.0;   // emulated speed in (0, 1]: idles after each batch (emulated)
  int fail_after = -1;  // testing aid: fail when pulling an item after this many; -1: never
};

// What a backend renders for the loop: one batch of items at a time.
class BatchRenderer {
 public:
  virtual ~BatchRenderer() = default;
  // How many items (>= 1) one render() call may take when `first` is the first. The loop
  // adds to `first` only items already the device's own (WorkSource::pending: the shared
  // queue's tail stays fine-grained and stealable) and none past fail_after. Default 1.
  virtual size_t batch_limit(const WorkItem& first) const;
  // Renders `items` (1..batch_limit, all of one view, in the order taken) into their view's
  // output and returns each item's stats, in the same order. Throws on a fault: the loop
  // then fails the frame (the engine re-renders what the device took and did not finish).
  virtual std::vector<KernelStats> render(const std::vector<WorkItem>& items) = 0;
};

// The loop's state over a device's life: its emulated speed and the items it has taken.
class DeviceLoop {
 public:
  // The backend has checked options.speed (in (0, 1]).
  explicit DeviceLoop(LoopOptions options);
  // For --perturb; 1 = full speed. Takes effect at the next frame.
  void set_speed(double speed) { speed_ = speed; }
  double speed() const { return speed_.load(); }
  int fail_after() const { return fail_after_; }

 private:
  friend class FrameLoop;
  const int fail_after_;
  std::atomic<double> speed_;
  std::atomic<int> taken_{0};  // items taken over the device's life, for fail_after
};

// How a backend's threads take part in a frame.
struct FrameMode {
  // Several threads call run() at once, each taking items for itself (a CPU device's
  // team). Items in progress together share the wall time (ItemTimeShare), so a frame's
  // item times still add up to the device's busy time. Needs speed 1: the emulated idle
  // follows one batch after another.
  bool concurrent = false;
  // Each batch runs on the calling thread alone: its CPU time is the batch's own work, so
  // the emulated idle scales that (time other processes took from the thread is not
  // multiplied by 1/speed, see SlowdownEmulator) and wall minus CPU time is reported as
  // stolen (DeviceReport::stolen_ms).
  bool on_calling_thread = false;
};

// One frame of one device through the loop; made when the device starts the frame (its
// clock, DeviceReport::time_ms, starts here).
class FrameLoop {
 public:
  // Refuses (refused(), before any item is taken) a frame whose kernel or sampling `info`'s
  // capabilities lack: the engine then drops the device and the others render the frame.
  FrameLoop(DeviceLoop& device, const DeviceInfo& info, const FrameJob& job, WorkSource& source,
            int index, FrameMode mode);
  bool refused() const { return report_.failed; }
  // Pulls and renders until nothing is left for the device, the injected failure or a
  // fault (then the report is failed with the error). Never throws. Thread-safe when
  // mode.concurrent; otherwise call it once.
  void run(BatchRenderer& renderer);
  // Fails the frame with `error` (a set-up fault of the backend). Thread-safe.
  void fail(const std::string& error);
  // True when the frame has failed: concurrent threads take no more items.
  bool stopped() const { return stop_.load(); }
  // Threads whose run() took at least one item (a testing aid of the CPU device's team).
  int takers() const { return takers_.load(); }
  // The report so far, for what only the backend measures (stolen time of its threads).
  // Not thread-safe: only before or after run().
  DeviceReport& report() { return report_; }
  // The report, its time_ms measured from the frame's start to now.
  DeviceReport finish();

 private:
  // Takes `first` and the batch it leads into `ids`; throws the injected failure.
  void take(BatchRenderer& renderer, uint32_t first, std::vector<uint32_t>& ids);
  // Renders ids[begin, end) (one view) as one batch, emulates, reports.
  void render_batch(BatchRenderer& renderer, const std::vector<uint32_t>& ids, size_t begin,
                    size_t end, SlowdownEmulator* slowdown);

  DeviceLoop& device_;
  const FrameJob& job_;
  WorkSource& source_;
  const int index_;
  const FrameMode mode_;
  const Stopwatch clock_;
  std::mutex mutex_;  // guards report_ while threads run
  DeviceReport report_;
  ItemTimeShare share_;  // concurrent mode: the items' times
  std::atomic<bool> stop_{false};
  std::atomic<int> takers_{0};
};

// A Device whose frames run through the loop: its info and its loop's emulated speed kept
// together (set_emulated_speed, for --perturb, changes both).
class LoopDevice : public Device {
 public:
  const DeviceInfo& info() const override { return info_; }
  void set_emulated_speed(double speed) override {
    loop_.set_speed(speed);
    info_.emulated_speed = speed;
  }

 protected:
  explicit LoopDevice(LoopOptions options) : loop_(options) {
    info_.emulated_speed = options.speed;
  }
  DeviceInfo info_;
  DeviceLoop loop_;
};

// The label of an emulated speed in a device's name, ", emulated speed 0.25" ("" at full
// speed): emulated slowness is always labelled, the same way on every backend.
std::string emulated_label(double speed);

// Splits `total_ms` over items in proportion to `weights` (their samples); by equal shares
// when every weight is 0. One batch has one time: this is each item's share of it.
std::vector<double> apportion(double total_ms, const std::vector<double>& weights);

}  // namespace multiray
