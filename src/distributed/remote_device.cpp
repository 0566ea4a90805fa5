#include "distributed/remote_device.h"

#include <csignal>

#include <algorithm>

#include "core/clock.h"
#include "distributed/wire.h"

namespace multiray::remote {

namespace {

// What every local device of the worker can do.
DeviceCapabilities common_caps(const std::vector<DeviceInfo>& devices) {
  DeviceCapabilities caps;
  if (devices.empty()) return caps;
  caps = devices.front().caps;
  for (const DeviceInfo& d : devices) {
    const auto keep = [&](std::vector<std::string>& mine, const std::vector<std::string>& theirs) {
      mine.erase(std::remove_if(mine.begin(), mine.end(),
                                [&](const std::string& x) {
                                  return std::find(theirs.begin(), theirs.end(), x) ==
                                         theirs.end();
                                }),
                 mine.end());
    };
    keep(caps.kernels, d.caps.kernels);
    keep(caps.sampling, d.caps.sampling);
  }
  caps.sampling.erase(std::remove(caps.sampling.begin(), caps.sampling.end(), "foveated"),
                      caps.sampling.end());  // its sample pattern does not travel
  return caps;
}

}  // namespace

int next_depth(int depth, double idle_ms, double frame_ms) {
  if (!(frame_ms > 0)) return depth;
  const double idle = idle_ms / frame_ms;
  if (idle > 0.03)
    depth += std::max(1, depth / 2);
  else if (idle < 0.005)
    depth -= 1;
  return std::clamp(depth, 2, 32);
}

RemoteDevice::RemoteDevice(Transport& transport, int rank, const HelloMessage& hello,
                           RemoteOptions options)
    : transport_(transport), rank_(rank), options_(options), local_(hello.devices) {
  info_.type = "rank";
  info_.spec = "rank:" + std::to_string(rank);
  info_.name = "rank " + std::to_string(rank) + " [";
  info_.threads = 0;
  for (size_t i = 0; i < local_.size(); ++i) {
    info_.name += (i ? " + " : "") + local_[i].name;
    info_.threads += local_[i].threads;
  }
  info_.name += "]";
  info_.caps = common_caps(local_);
  options_.depth = std::max(1, options_.depth);
}

void RemoteDevice::set_emulated_speed(double speed) {
  info_.emulated_speed = speed;
  if (!given_up_) transport_.send(rank_, kSpeed, encode_speed(speed));
}

FrameMessage RemoteDevice::frame_message(const FrameJob& job) const {
  FrameMessage m;
  m.epoch = epoch_;
  m.settings = job.settings;
  m.views = job.views;
  m.results = options_.results;
  for (const ViewSetup& v : job.views)
    m.spp_maps.push_back(v.spp_map ? *v.spp_map : std::vector<uint8_t>{});
  return m;
}

void RemoteDevice::ship(WorkSource& source, const std::vector<uint32_t>& ids, bool batched,
                        bool report_ready) {
  WorkMessage w;
  w.epoch = epoch_;
  w.batched = batched;
  w.report_ready = report_ready;
  w.ids = ids;
  for (uint32_t id : ids) w.items.push_back(source.item(id));
  transport_.send(rank_, kWork, encode(w));
}

size_t RemoteDevice::take_results(const Message& m, const FrameJob& job, DeviceReport& report) {
  // A frame given up on, whose image may have had another size (a plan's image_scale):
  // dropped unread. (The epoch leads every Result.)
  if (ByteReader(m.bytes).get<uint32_t>() != epoch_) return 0;
  ResultBounds bounds{0, 0, int(job.outputs->size())};
  if (!job.outputs->empty())
    bounds.width = job.outputs->front().width, bounds.height = job.outputs->front().height;
  const ResultMessage r = decode_result(m.bytes, bounds);
  report.result_bytes += m.bytes.size();  // as they crossed the (emulated) link
  for (const ItemResult& it : r.items) {
    const WorkItem& item = it.report.item;
    if (size_t(item.view) >= job.outputs->size()) throw WireError("result for an unknown view");
    Framebuffer& fb = (*job.outputs)[size_t(item.view)];
    if (item.rect.x1 > fb.width || item.rect.y1 > fb.height)
      throw WireError("result outside the image");
    const Vec3* src = it.pixels.data();
    for (int y = item.rect.y0; y < item.rect.y1; ++y, src += item.rect.width())
      std::copy(src, src + item.rect.width(), &fb.at(item.rect.x0, y));
    if (job.settings.feature_buffers) {
      if (it.features.empty()) throw WireError("result without the feature buffers asked for");
      unpack_features(it.features, item.rect, fb.features);
    }
    report.add(it.report, it.rays);
  }
  if (!r.local.empty()) local_times_ = r.local;
  idle_ms_ = std::max(idle_ms_, r.idle_ms);
  return r.items.size();
}

DeviceReport RemoteDevice::render(const FrameJob& job, WorkSource& source, int index) {
  DeviceReport report;
  const auto fail = [&](const std::string& why) {
    report.failed = true;
    report.error = "rank " + std::to_string(rank_) + ": " + why;
    return report;
  };
  if (given_up_) return fail("given up on earlier");
  if (!job.views.empty() && int(job.views[0].frame) == options_.kill_at_frame)
    std::raise(SIGKILL);  // testing aid: a master that dies mid-run (tests/mpi)
  for (const ViewSetup& v : job.views)
    if (v.foveation) return fail("foveated sampling does not run on other ranks");
  Stopwatch clock;
  ++epoch_;
  local_times_.clear();
  idle_ms_ = 0;
  bool pulled = false;  // items on demand this frame
  transport_.send(rank_, kFrame, encode(frame_message(job)));

  size_t owed = 0;  // items sent whose results have not come back
  DemandPipeline pipe{source.pull_on_ready(), options_.depth};
  std::vector<uint32_t> ids;
  if (const size_t own = source.pending(index); own > 0 && source.next(index, own, ids) > 0) {
    ship(source, ids, true, false);
    owed += ids.size(), pipe.sent(false);
  }
  bool exhausted = false;
  for (;;) {
    while (!exhausted && pipe.may_send()) {
      ids.clear();
      if (source.next(index, 1, ids) == 0) {
        exhausted = true;
      } else {
        ship(source, ids, false, pipe.on_ready);
        owed += ids.size(), pipe.sent(true), pulled = true;
      }
    }
    if (owed == 0) break;
    const auto now = Transport::Clock::now();
    std::optional<Message> m = transport_.receive(rank_, now + std::chrono::milliseconds(50));
    if (!m) {
      if (now - transport_.last_heard(rank_) > options_.timeout) {
        given_up_ = true;
        transport_.give_up(rank_);
        return fail("no answer for " +
                    std::to_string(options_.timeout.count() / 1000.0).substr(0, 4) +
                    " s (not even a heartbeat): given up on");
      }
      continue;
    }
    try {
      if (m->tag == kResult) {
        const size_t n = take_results(*m, job, report);
        if (n > 0) owed -= std::min(owed, n), pipe.result();
      } else if (m->tag == kReady) {
        if (decode_ready(m->bytes) == epoch_) pipe.ready();
      } else if (m->tag == kFailure) {
        const FailureMessage f = decode_failure(m->bytes);
        if (f.epoch == epoch_) return fail(f.error);
      }
    } catch (const WireError& e) {
      return fail(std::string("bad message: ") + e.what());
    }
  }
  report.time_ms = clock.elapsed_ms();
  if (options_.auto_depth && pulled && !pipe.on_ready)
    options_.depth = next_depth(options_.depth, idle_ms_, report.time_ms);
  for (const LocalDeviceTime& t : local_times_) report.local_ms.push_back(t.time_ms);
  return report;
}

}  // namespace multiray::remote
