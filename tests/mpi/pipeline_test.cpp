// The message pattern of items pulled on demand (distributed/pipeline.h), without MPI: the
// master's real policy (DemandPipeline) and a scripted worker exchange real encoded
// messages in virtual time over a link with latency and upload time. In the paper's form
// (Seo, Park & Ihm 2022, strategy I) a worker never holds more than one tile index, every
// index after the first is sent on a ready report, and the upload of tile k overlaps the
// rendering of tile k+1. Ours (deep) keeps two in flight and fails the first check.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <queue>
#include <vector>

#include "distributed/pipeline.h"
#include "distributed/protocol.h"
#include "distributed/wire.h"

namespace multiray::remote {
namespace pipeline_test {

enum class Kind { Sent, Ready, Result, RenderStart, RenderEnd };
struct Event {
  double t = 0;
  Kind kind = Kind::Sent;
  uint32_t tile = 0;
};

// A message on the link: delivered to the master (`to_master`) or to the worker at `t`.
struct InFlight {
  double t = 0;
  int order = 0;  // ties: in the order sent
  bool to_master = false;
  int tag = 0;
  std::vector<uint8_t> bytes;
  bool operator>(const InFlight& o) const { return t != o.t ? t > o.t : order > o.order; }
};

// One worker, `tiles` tiles of `render` ms each, `latency` ms each way, a result's upload
// `upload` ms (a large tile: longer than a round trip). The worker sends Ready before the
// Result when the Work message asks (as rank_worker.cpp does). Returns every event in time
// order as the master and the worker saw them.
std::vector<Event> exchange(DemandPipeline pipe, uint32_t tiles, double render = 10,
                            double latency = 2, double upload = 8) {
  std::vector<Event> log;
  std::priority_queue<InFlight, std::vector<InFlight>, std::greater<InFlight>> link;
  int order = 0;
  uint32_t next_tile = 0, results = 0;
  const auto master_sends = [&](double now) {
    while (next_tile < tiles && pipe.may_send()) {
      WorkMessage w{1, false, {next_tile}, {WorkItem{Rect{0, 0, 1, 1}, 0}}, pipe.on_ready};
      link.push({now + latency, order++, false, kWork, encode(w)});
      log.push_back({now, Kind::Sent, next_tile++});
      pipe.sent(true);
    }
  };
  double worker_free = 0;
  const auto worker_renders = [&](double now, const WorkMessage& w) {
    const double start = std::max(now, worker_free), end = start + render;
    log.push_back({start, Kind::RenderStart, w.ids[0]});
    log.push_back({end, Kind::RenderEnd, w.ids[0]});
    worker_free = end;
    if (w.report_ready) link.push({end + latency, order++, true, kReady, encode_ready(1)});
    ResultMessage r;
    r.epoch = 1;
    r.items.resize(1);
    r.items[0].report.id = w.ids[0];
    link.push({end + upload + latency, order++, true, kResult, encode(r)});
  };
  master_sends(0);  // the frame start stands for the first ready report
  while (!link.empty() && results < tiles) {
    const InFlight m = link.top();
    link.pop();
    if (!m.to_master) {
      worker_renders(m.t, decode_work(m.bytes));
    } else if (m.tag == kReady) {
      EXPECT_EQ(decode_ready(m.bytes), 1u);
      log.push_back({m.t, Kind::Ready, 0});
      pipe.ready();
      master_sends(m.t);
    } else {
      const ResultMessage r = decode_result(m.bytes, ResultBounds{64, 64, 1});
      log.push_back({m.t, Kind::Result, r.items[0].report.id});
      ++results;
      pipe.result();
      master_sends(m.t);
    }
  }
  EXPECT_EQ(results, tiles);
  std::stable_sort(log.begin(), log.end(),
                   [](const Event& a, const Event& b) { return a.t < b.t; });
  return log;
}

// Most tile indices sent and not yet rendered, at any moment.
int most_outstanding(const std::vector<Event>& log) {
  int out = 0, most = 0;
  for (const Event& e : log) {
    if (e.kind == Kind::Sent) most = std::max(most, ++out);
    if (e.kind == Kind::RenderEnd) --out;  // the worker is ready again
  }
  return most;
}

// Per tile, when its rendering started and when its result reached the master.
void times(const std::vector<Event>& log, std::map<uint32_t, double>& render_start,
           std::map<uint32_t, double>& result_at) {
  for (const Event& e : log) {
    if (e.kind == Kind::Result) result_at[e.tile] = e.t;
    if (e.kind == Kind::RenderStart) render_start[e.tile] = e.t;
  }
}

TEST(Pipeline, PaperFormHoldsOneTileAndSendsTheNextOnTheReadyReport) {
  const std::vector<Event> log = exchange(DemandPipeline{true, 2}, 6);
  EXPECT_EQ(most_outstanding(log), 1);
  // Every index after the first leaves at the moment a ready report arrives.
  int sent = 0, readies = 0;
  for (size_t i = 0; i < log.size(); ++i) {
    if (log[i].kind == Kind::Ready) ++readies;
    if (log[i].kind != Kind::Sent || log[i].tile == 0) continue;
    ++sent;
    ASSERT_GT(i, 0u);
    EXPECT_EQ(log[i - 1].kind, Kind::Ready) << "tile " << log[i].tile;
    EXPECT_EQ(log[i - 1].t, log[i].t) << "tile " << log[i].tile;
  }
  EXPECT_EQ(sent, 5);
  EXPECT_EQ(readies, 6);
}

TEST(Pipeline, PaperFormOverlapsTheUploadOfOneTileWithRenderingTheNext) {
  std::map<uint32_t, double> render_start, result_at;
  times(exchange(DemandPipeline{true, 2}, 4), render_start, result_at);
  ASSERT_EQ(result_at.size(), 4u);
  for (uint32_t k = 0; k + 1 < 4; ++k)
    EXPECT_LT(render_start[k + 1], result_at[k]) << "tile " << k;
  // The round trip is not hidden: the worker waits 2 x latency between tiles.
  EXPECT_DOUBLE_EQ(render_start[1] - render_start[0], 10 + 2 * 2);
  // One in flight without a ready report (--depth 1) is not the paper's form: the next
  // tile waits for the last one's upload too.
  render_start.clear(), result_at.clear();
  times(exchange(DemandPipeline{false, 1}, 4), render_start, result_at);
  EXPECT_GT(render_start[1], result_at[0]);
}

TEST(Pipeline, OursKeepsTwoInFlightAndWaitsLessBetweenTiles) {
  std::map<uint32_t, double> render_start, result_at;
  const std::vector<Event> log = exchange(DemandPipeline{false, 2}, 6);
  EXPECT_EQ(most_outstanding(log), 2);
  for (const Event& e : log) EXPECT_NE(e.kind, Kind::Ready);  // no ready reports
  times(log, render_start, result_at);
  // The next tile left before this one was rendered: less wait than the paper's 2 x 2 ms.
  EXPECT_LT(render_start[2] - render_start[1], 10 + 2 * 2);
}

TEST(Pipeline, WorkMessagesCarryTheReadyRequest) {
  WorkMessage w{3, false, {4}, {WorkItem{Rect{0, 0, 2, 2}, 0}}, true};
  EXPECT_TRUE(decode_work(encode(w)).report_ready);
  w.report_ready = false;
  EXPECT_FALSE(decode_work(encode(w)).report_ready);
  w.batched = true, w.report_ready = true;  // a batch reports no readiness
  EXPECT_THROW(decode_work(encode(w)), WireError);
  EXPECT_EQ(decode_ready(encode_ready(9)), 9u);
  EXPECT_THROW(decode_ready({1, 2}), WireError);
}

}  // namespace pipeline_test
}  // namespace multiray::remote
