#include "distributed/rank_worker.h"

#include <csignal>

#include <fmt/core.h>

#include "balance/hierarchy.h"
#include "core/error.h"
#include "distributed/pixel_codec.h"
#include "distributed/wire.h"

namespace multiray {

using namespace remote;

void obey_quit(Transport& transport, const Message& quit) {
  bool rank_lost = true;
  try {
    rank_lost = decode_quit(quit.bytes);
  } catch (const WireError&) {
  }
  if (rank_lost) transport.forgo_finalize();
}

void check_master_alive(Transport& transport, double timeout_s) {
  const double silent_s =
      std::chrono::duration<double>(Transport::Clock::now() - transport.last_heard(0)).count();
  if (silent_s <= timeout_s) return;
  transport.give_up(0);
  transport.forgo_finalize();
  throw DeviceError(fmt::format(
      "rank {}: nothing from the master (rank 0) for {:.1f} s (--worker-timeout {}): it has "
      "stopped or its machine is gone; this worker ends",
      transport.rank(), silent_s, timeout_s));
}

RankWorker::RankWorker(Transport& transport, std::vector<Device*> local, RenderSettings base,
                       RankWorkerOptions options)
    : transport_(transport),
      local_(std::move(local)),
      base_(std::move(base)),
      options_(std::move(options)) {
  std::unique_ptr<balance::Balancer> inner =
      balance::make_balancer(options_.balancer, int(local_.size()));
  inner_axis_ = inner->cut_axis();
  auto region = std::make_unique<balance::RegionBalancer>(std::move(inner), balance::Region{});
  region_ = region.get();
  engine_ = std::make_unique<Engine>(local_, std::move(region));
}

int RankWorker::serve() {
  for (;;) {
    std::optional<Message> m =
        transport_.receive(0, Transport::Clock::now() + std::chrono::seconds(1));
    check_master_alive(transport_, options_.master_timeout_s);
    if (!m) continue;
    try {
      switch (m->tag) {
        case kQuit:
          obey_quit(transport_, *m);
          return 0;
        case kFrame:
          start_frame(decode_frame(m->bytes));
          break;
        case kWork:
          render_work(decode_work(m->bytes));
          break;
        case kSpeed: {
          const double speed = decode_speed(m->bytes);
          for (Device* d : local_) d->set_emulated_speed(speed);
          break;
        }
        default:
          break;
      }
    } catch (const WireError& e) {
      fail(std::string("bad message from the master: ") + e.what());
    }
  }
}

void RankWorker::start_frame(const FrameMessage& m) {
  if (!m.views.empty() && int(m.views[0].frame) == options_.kill_at_frame)
    std::raise(SIGKILL);  // testing aid: a worker that dies mid-run
  epoch_ = m.epoch;
  failed_ = false;
  settings_ = m.settings;
  settings_.volume_style = base_.volume_style;
  results_ = m.results;
  views_ = m.views;
  spp_maps_ = m.spp_maps;
  for (size_t i = 0; i < views_.size(); ++i)
    views_[i].spp_map = spp_maps_[i].empty() ? nullptr : &spp_maps_[i];
  times_.assign(local_.size(), LocalDeviceTime{});
  idle_ms_ = 0;
  idle_since_.reset();
  try {
    check_result_encoding(results_);
  } catch (const std::invalid_argument& e) {  // a master built with zstd, this rank without
    fail(std::string("--result-encoding ") + e.what());
  }
}

void RankWorker::fail(const std::string& why) {
  failed_ = true;
  transport_.send(0, kFailure, encode(FailureMessage{epoch_, why}));
}

ItemResult RankWorker::render_item(uint32_t id, const WorkItem& item) {
  if (size_t(item.view) >= views_.size() || item.rect.x1 > views_[0].width ||
      item.rect.y1 > views_[0].height || item.rect.empty())
    throw WireError("work item outside the frame");
  // Across the master's band (Harada's second level), whichever way the master cut.
  const balance::CutAxis band = balance::band_axis(item.rect, views_[0].width, views_[0].height);
  const bool transposed =
      balance::lower_level_transposed(band, inner_axis_, options_.same_direction);
  region_->set_region(balance::Region{item.rect, item.view, transposed});
  const FrameRecord rec = engine_->render_frame(passes_++, views_, settings_, images_);
  ItemResult r;
  r.report.id = id;
  r.report.item = item;
  r.report.time_ms = rec.frame_ms;
  for (size_t d = 0; d < rec.devices.size(); ++d) {
    const DeviceReport& dr = rec.devices[d];
    r.report.busy_ms += dr.busy_ms;
    r.report.samples += double(dr.samples);
    r.rays += dr.rays;
    times_[d].time_ms += dr.time_ms, times_[d].busy_ms += dr.busy_ms;
  }
  const Framebuffer& fb = images_[size_t(item.view)];
  r.pixels.reserve(size_t(item.rect.area()));
  for (int y = item.rect.y0; y < item.rect.y1; ++y)
    r.pixels.insert(r.pixels.end(), &fb.at(item.rect.x0, y),
                    &fb.at(item.rect.x0, y) + item.rect.width());
  if (settings_.feature_buffers) r.features = packed_features(fb.features, item.rect);
  return r;
}

void RankWorker::render_work(const WorkMessage& m) {
  if (m.epoch != epoch_ || failed_) return;  // a frame given up on, or already failed
  if (idle_since_)
    idle_ms_ +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *idle_since_)
            .count();
  ResultMessage batch{epoch_, results_, {}, {}, 0};
  for (size_t i = 0; i < m.items.size(); ++i) {
    ItemResult r;
    try {
      r = render_item(m.ids[i], m.items[i]);
    } catch (const std::exception& e) {  // every local device failed, or a bad item
      return fail(e.what());
    }
    if (m.batched) {
      batch.items.push_back(std::move(r));
    } else {
      if (i + 1 == m.items.size()) idle_since_ = std::chrono::steady_clock::now();
      // The paper's form: ready first (a few bytes), so the next item is on its way while
      // this one's pixels upload.
      if (m.report_ready) transport_.send(0, kReady, encode_ready(epoch_));
      ResultMessage one{epoch_, results_, {}, times_, idle_ms_};
      one.items.push_back(std::move(r));
      transport_.send(0, kResult, encode(one));
    }
  }
  if (m.batched) {
    batch.local = times_;
    batch.idle_ms = idle_ms_;
    transport_.send(0, kResult, encode(batch));
  }
}

}  // namespace multiray
