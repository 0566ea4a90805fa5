// Traces: written and read back unchanged; malformed ones refused with the line number;
// replayed through the simulator they give back the recorded per-device work.
#include <gtest/gtest.h>

#include <sstream>

#include "balance/trace.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace trace_test {

// A run of `spec` on the simulator, recorded as a trace.
Trace record(const std::string& spec, const std::vector<double>& speeds, int frames) {
  const FrameShape shape{80, 48, 2, {}};
  auto balancer = make_balancer(spec, int(speeds.size()));
  const auto run = simulate_run(*balancer, shape, testing::constant(speeds),
                                testing::uneven_cost(shape), frames);
  Trace t;
  t.balancer = balancer->spec();
  for (double s : speeds) t.devices.push_back({"sim device", s});
  for (const SimFrame& f : run) t.frames.push_back(f.stats);
  return t;
}

std::string text(const Trace& t) {
  std::ostringstream out;
  write_trace(out, t);
  return out.str();
}

TEST(Trace, RoundTripsExactly) {
  const Trace t = record("hybrid", {1.0, 0.5}, 4);
  std::istringstream in(text(t));
  const Trace back = read_trace(in);
  EXPECT_EQ(text(back), text(t));
  ASSERT_EQ(back.frames.size(), 4u);
  EXPECT_EQ(back.devices[1].speed, 0.5);
  EXPECT_EQ(back.frames[2].devices[1].items.size(), t.frames[2].devices[1].items.size());
  EXPECT_EQ(back.frames[2].devices[1].time_ms, t.frames[2].devices[1].time_ms);
  // A device's frame totals are not written: the reader sums them from its items, and
  // the balancers' update() reads them (work_done).
  for (size_t f = 0; f < t.frames.size(); ++f)
    for (size_t d = 0; d < t.devices.size(); ++d) {
      const DeviceFrameStats &want = t.frames[f].devices[d], &got = back.frames[f].devices[d];
      ASSERT_GT(want.samples, 0) << f << " " << d;
      EXPECT_EQ(got.samples, want.samples) << "frame " << f << " device " << d;
      EXPECT_EQ(got.pixels, want.pixels) << "frame " << f << " device " << d;
      EXPECT_EQ(got.alive, want.alive) << "frame " << f << " device " << d;
    }
}

// A device left out of a frame (time record 2) and the balancer's models (model records)
// come back as written.
TEST(Trace, LeftOutDevicesAndModelsRoundTrip) {
  Trace t = record("hybrid", {1.0, 0.5}, 3);
  // Device 1 left out of frame 1: device 0 renders its items too (a trace tiles each frame).
  std::vector<ItemReport>& mine = t.frames[1].devices[0].items;
  const std::vector<ItemReport>& rested = t.frames[1].devices[1].items;
  mine.insert(mine.end(), rested.begin(), rested.end());
  t.frames[1].devices[1] = DeviceFrameStats{};
  t.frames[1].devices[1].rested = true;
  t.models.assign(3, {});
  t.models[2] = {DeviceCostModel{1e-3, 2.5, 0.25, false}, DeviceCostModel{93.25, 75.5, 1.5, true}};
  std::istringstream in(text(t));
  const Trace back = read_trace(in);
  EXPECT_EQ(text(back), text(t));
  EXPECT_TRUE(back.frames[1].devices[1].rested);
  EXPECT_TRUE(back.frames[1].devices[1].alive);
  EXPECT_FALSE(back.frames[1].devices[0].rested);
  ASSERT_EQ(back.models.size(), 3u);
  EXPECT_TRUE(back.models[0].empty());
  ASSERT_EQ(back.models[2].size(), 2u);
  EXPECT_EQ(back.models[2][1].fixed_ms, 75.5);
  EXPECT_EQ(back.models[2][1].fixed_sigma, 1.5);
  EXPECT_EQ(back.models[2][1].speed, 93.25);
  EXPECT_TRUE(back.models[2][1].determined);
  EXPECT_FALSE(back.models[2][0].determined);
}

TEST(Trace, MalformedTracesAreRefusedWithTheLine) {
  const std::string good = "multiray-trace 1\nbalancer uniform\ndevice 0 1 cpu\nframe 0 4 4 1\n";
  for (const auto& [bad, line] : std::vector<std::pair<std::string, std::string>>{
           {"not a trace\n", "line 1"},
           {good + "item 0 0 0 0 0 5 4 16 1 1\n", "line 5"},    // x1 beyond the width
           {good + "item 1 0 0 0 0 4 4 16 1 1\n", "line 5"},    // no device 1
           {good + "time 0 1 nan 1\n", "line 5"},               // not a finite number
           {good + "item 0 0 0 0 0 4 4 16 1\n", "line 5"},      // a field missing
           {good + "item 0 0 0 0 0 4 4 16 1 1 9\n", "line 5"},  // one too many
           {"multiray-trace 1\nitem 0 0 0 0 0 4 4 16 1 1\n", "line 2"},
           {"multiray-trace 1\ndevice 3 1 cpu\n", "line 2"},
           {"multiray-trace 1\nbogus\n", "line 2"},
           {good + "device 1 1 late\ntime 1 1 1 1\n", "line 5"},  // a device after a frame
           {good + "frame 1 0 4 1\n", "line 5"},
           {good + "time 0 3 1 1\n", "line 5"},      // no such state
           {good + "model 0 -1 0 1 1\n", "line 5"},  // a negative fixed cost
           {good + "model 0 1 0 1\n", "line 5"},     // a field missing
           {"multiray-trace 1\nmodel 0 1 0 1 1\n", "line 2"}}) {
    std::istringstream in(bad);
    try {
      read_trace(in);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(line), std::string::npos) << e.what();
    }
  }
}

// A trace without frames (header only, or cut off after its header) has nothing to replay:
// refused when read, as `multiray simulate` must (it crashed on trace.frames[0]).
TEST(Trace, ATraceWithoutFramesIsRefused) {
  for (const std::string& bare :
       {std::string("multiray-trace 1\n"), std::string("multiray-trace 1\nbalancer queue\n"),
        std::string("multiray-trace 1\nbalancer queue\ndevice 0 1 a\n")}) {
    std::istringstream in(bare);
    try {
      read_trace(in);
      ADD_FAILURE() << "accepted: " << bare;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("no frames"), std::string::npos) << e.what();
    }
  }
}

// Items must tile each frame exactly (every pixel of every view once): two devices over
// the same pixels, or a frame half covered, are refused naming the frame's line, never
// replayed as if they were whole (they gave an efficiency of 3.0, or a free half).
TEST(Trace, ItemsThatDoNotTileTheFrameAreRefused) {
  const std::string head = "multiray-trace 1\nbalancer uniform\ndevice 0 1 a\ndevice 1 1 b\n";
  const std::string ok =
      "frame 0 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 2 16 2 2\n"
      "time 1 1 2 2\nitem 1 1 0 0 2 8 4 16 2 2\n";
  for (const auto& [bad, what] : std::vector<std::pair<std::string, std::string>>{
           {"frame 0 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 4 32 2 2\n"
            "time 1 1 2 2\nitem 1 1 0 0 0 8 4 32 2 2\n",
            "line 5 (frame 0): pixel (0,0) of view 0 is covered twice"},
           {"frame 0 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 2 16 2 2\ntime 1 1 0 0\n",
            "line 5 (frame 0): pixel (0,2) of view 0 is not covered"},
           {ok + "frame 1 8 4 2\ntime 0 1 2 2\nitem 0 0 0 0 0 8 4 32 2 2\n",  // view 1 missing
            "line 10 (frame 1): pixel (0,0) of view 1 is not covered"},
           {ok + "frame 1 8 4 1\ntime 0 1 0 0\ntime 1 1 0 0\n",  // no items at all
            "line 10 (frame 1): pixel (0,0) of view 0 is not covered"}}) {
    std::istringstream in(head + bad);
    try {
      read_trace(in);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
}

// What our own writer produces is accepted: a device that failed (time state 0) keeps the
// items it finished, the others re-render the rest; a device left out (state 2) has none;
// frames of several views.
TEST(Trace, DroppedAndRestedDevicesOverManyViewsAreAccepted) {
  std::istringstream in(
      "multiray-trace 1\nbalancer queue\ndevice 0 1 a\ndevice 1 1 b\ndevice 2 1 c\n"
      "frame 0 4 2 2\ntime 0 0 1 1\nitem 0 0 0 0 0 2 2 4 1 1\n"
      "time 1 1 3 3\nitem 1 1 0 2 0 4 2 4 1 1\nitem 1 2 1 0 0 4 2 8 2 2\n"
      "time 2 2 0 0\n"
      "frame 1 4 2 2\ntime 0 0 0 0\ntime 1 1 2 2\nitem 1 0 1 0 0 4 2 8 1 1\n"
      "time 2 1 2 2\nitem 2 1 0 0 0 4 2 8 1 1\n");
  const Trace t = read_trace(in);
  ASSERT_EQ(t.frames.size(), 2u);
  EXPECT_FALSE(t.frames[0].devices[0].alive);
  EXPECT_EQ(t.frames[0].devices[0].items.size(), 1u);
  EXPECT_TRUE(t.frames[0].devices[2].rested);
}

// Replaying a trace with the balancer that recorded it reproduces every frame's plan and
// the items each device rendered, exactly.
TEST(Trace, ReplayGivesTheRecordedPerDeviceWork) {
  for (const char* spec : {"hybrid", "queue:tile=16", "semi-static", "dlb"}) {
    const Trace t = record(spec, {1.0, 0.5, 0.25}, 6);
    std::istringstream in(text(t));
    const Trace read = read_trace(in);
    auto balancer = make_balancer(spec, 3);
    const auto replay = replay_trace(read, *balancer);
    ASSERT_EQ(replay.size(), t.frames.size());
    for (size_t f = 0; f < replay.size(); ++f)
      for (size_t d = 0; d < 3; ++d) {
        const auto& want = t.frames[f].devices[d].items;
        const auto& got = replay[f].stats.devices[d].items;
        ASSERT_EQ(got.size(), want.size()) << spec << " frame " << f << " device " << d;
        for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].item, want[i].item) << spec;
      }
  }
}

// Items the recording never saw (another balancer's split) cost what the recorded cost
// density says: replaying a uniform trace's costs under hybrid keeps the frame's total.
TEST(Trace, CostOfOtherItemsFollowsTheRecordedDensity) {
  const Trace t = record("uniform", {1.0, 1.0}, 1);
  const FrameShape& shape = t.frames[0].shape;
  const CostFn cost = trace_cost(t, 0, shape);
  double recorded = 0;
  for (const auto& d : t.frames[0].devices)
    for (const ItemReport& r : d.items) recorded += r.time_ms;
  double whole = 0;
  for (int v = 0; v < shape.views; ++v)
    for (int y = 0; y < shape.height; y += 3)
      whole += cost(WorkItem{Rect{0, y, shape.width, std::min(y + 3, shape.height)}, v});
  EXPECT_NEAR(whole, recorded, 1e-3 * recorded);
}

}  // namespace trace_test
}  // namespace multiray::balance
