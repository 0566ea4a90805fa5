// Traces: what every work item cost on the device that rendered it, frame by frame, in a
// compact text format (docs/traces.md) that the simulator can replay. Recorded by
// `multiray render|bench --trace FILE`; replayed by replay_trace() (and, later,
// `multiray simulate`) through the very balancer and Dispatcher code the engine runs.
//
// Format, one record per line, fields separated by single spaces:
//   multiray-trace 1
//   balancer SPEC
//   device INDEX SPEED NAME...          (SPEED: emulated speed factor, 1 = full)
//   frame FRAME WIDTH HEIGHT VIEWS      (starts a frame; the shape the items refer to)
//   time DEVICE ALIVE TIME_MS BUSY_MS   (the device's frame; ALIVE 1 or 0)
//   item DEVICE ID VIEW X0 Y0 X1 Y1 SAMPLES TIME_MS BUSY_MS
// Times are milliseconds measured inside the device (TIME wall incl. emulated idle, BUSY
// rendering only), written with 17 significant digits so a read trace equals the written one.
#pragma once

#include <functional>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "balance/simulate.h"
#include "balance/stats.h"

namespace multiray::balance {

struct TraceDevice {
  std::string name;
  double speed = 1.0;  // emulated speed factor when recorded (1: full speed)
};

struct Trace {
  std::string balancer;
  std::vector<TraceDevice> devices;
  std::vector<FrameStats> frames;  // shapes carry size and views (no pixel weights)
  // Per frame, the balancer's cost model of each device as it planned the frame (`model`
  // records; participation.h); an empty list where none was recorded.
  std::vector<std::vector<DeviceCostModel>> models;
};

// Writes a trace as frames finish. Check the stream after the last frame.
class TraceWriter {
 public:
  TraceWriter(std::ostream& out, const std::string& balancer,
              const std::vector<TraceDevice>& devices);
  // `models`: the balancer's model of each device for the frame (Plan::models), or none.
  void frame(const FrameStats& stats, const std::vector<DeviceCostModel>& models = {});

 private:
  std::ostream& out_;
};

void write_trace(std::ostream& out, const Trace& trace);
// Throws std::invalid_argument naming the line for anything malformed: an unknown record,
// a missing or non-numeric field, a number out of range, a device or frame out of order;
// a trace without frames; a frame whose items (all devices', a dropped one's included)
// do not cover each pixel of each view exactly once (naming the frame's line).
Trace read_trace(std::istream& in);

// The cost (ms at speed 1) of an item of frame `frame_index` of `trace`: an item recorded
// exactly as is costs its recorded time × its device's speed; any other item costs the
// recorded cost density (per unit of weight, spread evenly over each recorded item) summed
// over its pixels. `shape` supplies pixel weights (may be empty).
CostFn trace_cost(const Trace& trace, size_t frame_index, const FrameShape& shape);

// trace_cost() of each frame of one trace, built when first asked for and then kept, so
// that the replays of one study (every balancer at every device count) share them. Each
// holds a frame-sized summed-area table (8 bytes a pixel, 265 MB at 7680x4320): built once
// per replay, the tables were most of an 8K study's time (docs/benchmarks.md). `trace`
// must outlive this object; not thread-safe.
class TraceCosts {
 public:
  explicit TraceCosts(const Trace& trace);
  const CostFn& at(size_t frame_index);
  const Trace& trace() const { return trace_; }
  size_t built() const { return built_; }  // cost tables built so far

 private:
  const Trace& trace_;
  std::vector<CostFn> costs_;
  size_t built_ = 0;
};

// Replays `trace` through `balancer` on simulated devices, frame by frame, with
// trace_cost() as each frame's cost: `frames` frames (0: as many as the trace has; more
// cycle through the trace), on `devices_at(frame)` (default: one device per traced device
// at its recorded speed), behind `link`. The balancer must be made for that many devices.
std::vector<SimFrame> replay_trace(
    const Trace& trace, Balancer& balancer,
    const std::function<std::vector<SimDevice>(int frame)>& devices_at = {},
    const SimLink& link = {}, int frames = 0, uint64_t seed = 0);

// The same replay, each frame handed to `each` (with its index f in 0..frames-1) as soon as
// the balancer has seen it, and then dropped: memory stays that of one frame however many
// frames are replayed (`multiray simulate` runs up to 10^6 frames on 4096 devices).
// `costs` (optional) supplies the frames' costs and keeps them for the next replay; it
// must have been made for this `trace` (else std::invalid_argument).
void replay_trace_each(const Trace& trace, Balancer& balancer,
                       const std::function<std::vector<SimDevice>(int frame)>& devices_at,
                       const SimLink& link, int frames, uint64_t seed,
                       const std::function<void(int f, SimFrame&& frame)>& each,
                       TraceCosts* costs = nullptr);

}  // namespace multiray::balance
