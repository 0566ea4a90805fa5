// A worker rank seen by the master as one more Device (DESIGN.md: "a remote rank is one
// more device to the master"). render() pulls items from the frame's WorkSource like any
// device and ships them to the worker, which renders them over its own local devices and
// sends the pixels back (protocol.h). Two ways to ship, following Seo et al. 2022 (§4):
//
//  - the items the plan assigned to this device (static plans: Seo's strategy II, OSPRay's
//    tile ownership, a Harada band) go in one message at the start of the frame and come
//    back in one message at its end ("batched": one exchange per frame);
//  - items pulled on demand (the shared queue: Seo's strategy I) travel in one of two
//    forms (pipeline.h). The paper's, when the plan asks for it (queue's default,
//    WorkSource::pull_on_ready): one item at a time, the next sent when the worker
//    reports the last one rendered, so only the upload of its pixels overlaps rendering
//    the next. Otherwise ours: items are kept `depth` deep at the worker, so the worker
//    finds its next item waiting and the round trip hides too. With `auto` depth the
//    depth adapts from frame to frame to what the worker measured: it grows while the
//    worker waited for items (more than 3% of its frame), and shrinks while it never did
//    (under 0.5%), so a link's round trip stays hidden without holding more items than
//    needed at the end of a frame.
//
// Time is measured by the master from the start of the frame to the last result (the time
// the master waits for this worker, link included); each item's busy time is measured on
// the worker. A worker that sends nothing (no heartbeat either) for `timeout` is given up
// on: render() reports failed, the engine re-renders what it owed, and it is never asked
// again.
#pragma once

#include <chrono>
#include <vector>

#include "device/device.h"
#include "distributed/pipeline.h"
#include "distributed/protocol.h"
#include "distributed/transport.h"

namespace multiray::remote {

struct RemoteOptions {
  std::chrono::milliseconds timeout{10000};  // silence after which a worker is given up on
  int depth = 2;                             // ours: items on demand kept at the worker, >= 1
  bool auto_depth = true;                    // adapt depth (starting from `depth`)
  int kill_at_frame = -1;  // testing aid: the master SIGKILLs itself as it starts this frame
  ResultEncoding results = ResultEncoding::float32;  // --result-encoding, sent with each frame
};

// The depth of the next frame from this frame's: the worker waited `idle_ms` for items
// on demand during `frame_ms`. Grows by half while idle > 3%, shrinks by one while idle <
// 0.5%, stays in [2, 32].
int next_depth(int depth, double idle_ms, double frame_ms);

class RemoteDevice : public Device {
 public:
  // Worker `rank` (>= 1) of `transport`, which said hello with `hello`.
  RemoteDevice(Transport& transport, int rank, const HelloMessage& hello, RemoteOptions options);

  const DeviceInfo& info() const override { return info_; }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override;
  void set_emulated_speed(double speed) override;

  int rank() const { return rank_; }
  // The worker's local devices, as it described them.
  const std::vector<DeviceInfo>& local_devices() const { return local_; }
  // Per local device, its time in the last frame (Harada's deviation over every device).
  const std::vector<LocalDeviceTime>& last_local_times() const { return local_times_; }
  bool given_up() const { return given_up_; }
  int depth() const { return options_.depth; }

 private:
  // Sends `ids` as one Work message (`report_ready`: the paper's form, pipeline.h).
  void ship(WorkSource& source, const std::vector<uint32_t>& ids, bool batched, bool report_ready);
  // Takes one result message into job.outputs and `report`; returns the items it carried.
  size_t take_results(const Message& m, const FrameJob& job, DeviceReport& report);
  FrameMessage frame_message(const FrameJob& job) const;

  Transport& transport_;
  int rank_;
  RemoteOptions options_;
  DeviceInfo info_;
  std::vector<DeviceInfo> local_;
  std::vector<LocalDeviceTime> local_times_;
  double idle_ms_ = 0;  // the worker's wait for items this frame
  uint32_t epoch_ = 0;
  bool given_up_ = false;
};

}  // namespace multiray::remote
