// The messages between the master (rank 0) and its workers. One frame of one remote
// device, as the master's RemoteDevice drives it:
//
//   master                                   worker
//   Frame{epoch, views, settings}   ─────►   sets up the frame
//   Work{epoch, items, batched}     ─────►   renders the items over its local devices
//                                   ◄─────   Result{epoch, items with pixels}: one per item,
//                                            or one per Work message when `batched`
//   (more Work as the master pulls items for it; the frame ends when nothing is owed)
//
// Items pulled on demand in the paper's form (Seo et al. 2022, strategy I; balance::Plan::
// pull_on_ready) go one at a time with `report_ready` set: the worker sends Ready{epoch}
// as soon as it has rendered the item, then that item's Result, and the master answers
// the Ready with the next item. The upload of one result thus overlaps rendering the next
// item, but every item still waits for one round trip. (The Frame message stands for the
// first ready report: the master sends the first item right after it.)
//
// Scene (master → worker, first, only with --scene-from master: scene_codec.h) carries
// the scene. Hello (worker → master, once, before any frame) says what the worker offers or why it
// could not start, with the fingerprint of what decides its pixels (fingerprint.h); Speed sets the
// emulated speed of its devices (--perturb); Quit ends it, saying whether the master gave up on a
// rank (then the worker must not call MPI_Finalize, which waits for every rank of the job:
// transport.h). `epoch` numbers the master's requests to that worker, so results of a frame the
// master gave up on are recognised and dropped. (Heartbeats belong to the transport.)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "distributed/fingerprint.h"
#include "util/result_encoding.h"

namespace multiray::remote {

enum Tag : int { kHello = 1, kFrame, kWork, kResult, kFailure, kSpeed, kQuit, kScene, kReady };

struct HelloMessage {
  bool ok = true;
  std::string error;                // why the worker cannot render (ok = false)
  std::vector<DeviceInfo> devices;  // its local devices
  PixelFingerprint fingerprint;     // what decides its pixels, checked by the master
};

struct FrameMessage {
  uint32_t epoch = 0;
  RenderSettings settings;  // volume_style is not sent: the worker keeps its own
  std::vector<ViewSetup> views;
  // Adaptive sampling: each view's sample map (empty: none), for views[i].spp_map.
  std::vector<std::vector<uint8_t>> spp_maps;
  // How the worker sends this frame's pixels back (--result-encoding: the master's).
  ResultEncoding results = ResultEncoding::float32;
};

struct WorkMessage {
  uint32_t epoch = 0;
  bool batched = false;  // true: send every result in one message after the last item
  std::vector<uint32_t> ids;
  std::vector<WorkItem> items;
  // true (never with `batched`): send Ready as soon as each item is rendered, before its
  // Result (the paper's form of items on demand).
  bool report_ready = false;
};

// One local device's part of the worker's frame so far: what Harada's deviation is
// measured over in a hierarchy.
struct LocalDeviceTime {
  double time_ms = 0, busy_ms = 0;
};

struct ItemResult {
  ItemReport report;  // measured on the worker; time_ms = its wall time there
  uint64_t rays = 0;
  std::vector<Vec3> pixels;  // the item's rect, row-major
  // The same pixels' feature buffers, FeatureBuffers::kFloats packed floats each, when the
  // frame asks for them (RenderSettings::feature_buffers); empty otherwise. They travel in
  // the frame's result encoding, as the pixels do.
  std::vector<float> features;
};

struct ResultMessage {
  uint32_t epoch = 0;
  // How the items' pixels travel (pixel_codec.h); decoding gives them back as floats.
  ResultEncoding encoding = ResultEncoding::float32;
  std::vector<ItemResult> items;
  std::vector<LocalDeviceTime> local;  // per local device, the frame so far
  // The frame so far: ms the worker waited for its next item after finishing one (work
  // in transit: the pipeline of items on demand was too shallow).
  double idle_ms = 0;
};

struct FailureMessage {
  uint32_t epoch = 0;
  std::string error;
};

std::vector<uint8_t> encode(const HelloMessage& m);
std::vector<uint8_t> encode(const FrameMessage& m);
std::vector<uint8_t> encode(const WorkMessage& m);
std::vector<uint8_t> encode(const ResultMessage& m);
std::vector<uint8_t> encode(const FailureMessage& m);
std::vector<uint8_t> encode_ready(uint32_t epoch);
std::vector<uint8_t> encode_speed(double speed);
std::vector<uint8_t> encode_quit(bool rank_lost);

// What a Result may hold: every item inside a `width` x `height` frame of `views` views,
// and no more pixels in all than the frame has. The master passes its frame, so that no
// message makes it allocate more than that.
struct ResultBounds {
  int width = 0, height = 0, views = 1;
};

// Each throws WireError for a message that does not parse or holds impossible values.
HelloMessage decode_hello(const std::vector<uint8_t>& bytes);
FrameMessage decode_frame(const std::vector<uint8_t>& bytes);
WorkMessage decode_work(const std::vector<uint8_t>& bytes);
ResultMessage decode_result(const std::vector<uint8_t>& bytes, const ResultBounds& bounds);
FailureMessage decode_failure(const std::vector<uint8_t>& bytes);
// The epoch of a Ready message.
uint32_t decode_ready(const std::vector<uint8_t>& bytes);
double decode_speed(const std::vector<uint8_t>& bytes);
// True when the master gave up on a rank.
bool decode_quit(const std::vector<uint8_t>& bytes);

}  // namespace multiray::remote
