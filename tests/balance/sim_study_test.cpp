// Simulation studies: the speed distributions and links they accept, and what a study of
// a known trace must give.
#include <gtest/gtest.h>

#include <cmath>

#include "balance/sim_study.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace sim_study_test {

// A trace of `frames` frames whose cost is 1 µs per pixel, recorded on one device.
Trace flat_trace(int frames) {
  const FrameShape shape{64, 48, 1, {}};
  auto b = make_balancer("uniform", 1);
  Trace t;
  t.balancer = b->spec();
  t.devices.push_back({"recorder", 1.0});
  for (const auto& f :
       simulate_run(*b, shape, testing::constant({1.0}), uniform_cost(shape, 1e-3), frames))
    t.frames.push_back(f.stats);
  return t;
}

TEST(SimStudy, SpeedDistributions) {
  EXPECT_EQ(device_speeds("equal", 3, 0), (std::vector<double>{1, 1, 1}));
  EXPECT_EQ(device_speeds("linear:0.5", 3, 0), (std::vector<double>{1, 0.75, 0.5}));
  EXPECT_EQ(device_speeds("list:1/0.25", 3, 0), (std::vector<double>{1, 0.25, 1}));
  const auto r = device_speeds("random:0.2", 100, 7);
  for (double v : r) EXPECT_TRUE(v >= 0.2 && v <= 1) << v;
  EXPECT_EQ(r, device_speeds("random:0.2", 100, 7));  // deterministic per seed
  EXPECT_NE(r, device_speeds("random:0.2", 100, 8));
  for (const char* bad : {"", "fast", "linear:0", "linear:2", "list:", "list:1/x", "random:-1",
                          "equal:1", "linear:nan"})
    EXPECT_THROW(device_speeds(bad, 4, 0), std::invalid_argument) << bad;
  EXPECT_THROW(device_speeds("equal", 0, 0), std::invalid_argument);
  EXPECT_THROW(device_speeds("equal", 5000, 0), std::invalid_argument);
}

TEST(SimStudy, Links) {
  // The grammar of render --distributed's --link (util/link.h), one for both commands.
  EXPECT_EQ(simulated_link("wifi").latency_ms, 5);
  EXPECT_FALSE(simulated_link("none").active());
  const SimLink l = simulated_link("2,100");
  EXPECT_EQ(l.latency_ms, 2);
  EXPECT_EQ(l.mbit_per_s, 100);
  EXPECT_TRUE(l.shared_master);
  EXPECT_FALSE(simulated_link("2,100,separate").shared_master);
  for (const char* bad : {"", "fast", "2", "2:100", "-1,10", "x,10", "1,inf", "1,2,other"})
    EXPECT_THROW(simulated_link(bad), std::invalid_argument) << bad;
}

// simulate --result-encoding: what a result pixel costs on the link, and a link that
// carries compressed results charges their compressed bytes.
TEST(SimStudy, ResultEncodingsSetTheBytesAPixelCosts) {
  EXPECT_EQ(simulated_bytes_per_pixel("rgba8"), 4);
  EXPECT_EQ(simulated_bytes_per_pixel("float"), 12);
  EXPECT_EQ(simulated_bytes_per_pixel("half"), 6);
  EXPECT_EQ(simulated_bytes_per_pixel("float+zstd", 0.25), 3);
  EXPECT_EQ(simulated_bytes_per_pixel("half+zstd", 0.5), 3);
  EXPECT_EQ(simulated_bytes_per_pixel("float", 0.25), 12);  // the ratio is zstd's alone
  // The default ratio is the measured one, below 1 (zstd does compress a rendered frame).
  const double measured = simulated_bytes_per_pixel("float+zstd");
  EXPECT_GT(measured, 0);
  EXPECT_LT(measured, 12);
  for (const char* bad : {"", "rgb8", "zstd", "float+lz4"})
    EXPECT_THROW(simulated_bytes_per_pixel(bad), std::invalid_argument) << bad;
  for (double bad : {0.0, 1.5, double(NAN)})
    EXPECT_THROW(simulated_bytes_per_pixel("half+zstd", bad), std::invalid_argument) << bad;

  // Two devices send half a 64x48 frame each over a shared 1-byte-per-ms link: at 3
  // bytes a pixel (float+zstd at 0.25), 1536 px x 3 bytes = 4608 ms each, in turn.
  auto b = make_balancer("uniform", 2);
  const FrameShape shape{64, 48, 1, {}};
  SimLink link;
  link.mbit_per_s = 8e-3;
  link.bytes_per_pixel = simulated_bytes_per_pixel("float+zstd", 0.25);
  const auto f = simulate_linked(b->plan(shape, 0), shape, {SimDevice{}, SimDevice{}},
                                 uniform_cost(shape, 0.01), link);
  EXPECT_NEAR(f.frame_ms, 15.36 + 2 * 4608, 1e-6);
}

TEST(SimStudy, WithoutLinkAStaticSplitOfEqualDevicesIsIdeal) {
  StudyConfig c;
  c.speeds = {1, 1, 1, 1};
  const StudyResult r = run_study(flat_trace(5), "uniform", c);
  EXPECT_EQ(r.devices, 4);
  EXPECT_NEAR(r.mean_ideal_ms, 64 * 48 * 1e-3 / 4, 1e-9);
  EXPECT_NEAR(r.efficiency, 1.0, 1e-6);  // costs pass through float pixel maps
}

TEST(SimStudy, ASlowLinkCostsEfficiencyAndSlowerDevicesHideIt) {
  StudyConfig c;
  c.speeds = device_speeds("equal", 8, 0);
  c.link = SimLink::wifi();
  const Trace t = flat_trace(4);
  const double fast = run_study(t, "uniform", c).efficiency;
  c.slowdown = 1000;  // rendering now dwarfs the link
  const double slow = run_study(t, "uniform", c).efficiency;
  EXPECT_LT(fast, 0.5);
  EXPECT_GT(slow, 0.8);
  EXPECT_THROW(run_study(t, "nonsense", c), std::invalid_argument);
  c.warmup = 4;  // no frame left to count
  EXPECT_THROW(run_study(t, "uniform", c), std::invalid_argument);
}

// The ideal is taken against each frame's own noisy speeds: one device is always ideal,
// and no study passes 1, however lucky its frames' noise.
TEST(SimStudy, NoisyFramesNeverMakeAnEfficiencyAboveOne) {
  const Trace t = flat_trace(3);
  StudyConfig c;
  c.frames = 12;
  c.frame_noise = 0.3;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    c.seed = seed;
    c.speeds = {1};
    EXPECT_NEAR(run_study(t, "uniform", c).efficiency, 1.0, 1e-6) << seed;
    c.speeds = {1, 0.5, 0.7};
    for (const char* spec : {"uniform", "static", "queue", "hybrid"})
      EXPECT_LE(run_study(t, spec, c).efficiency, 1.0 + 1e-6) << spec << " seed " << seed;
  }
}

// The studies of one simulation share the traced frames' cost tables: each is built
// once, however many balancers and device counts replay it, and sharing changes no result.
TEST(SimStudy, StudiesShareEachFramesCostTableAndGiveTheSameResults) {
  const Trace t = flat_trace(3);
  StudyConfig c;
  c.speeds = {1, 0.5, 0.25};
  c.frames = 10;  // the 3 traced frames, cycled
  TraceCosts shared(t);
  for (const char* spec : {"queue", "semi-static", "hybrid"}) {
    const StudyResult alone = run_study(t, spec, c);
    const StudyResult with = run_study(t, spec, c, &shared);
    EXPECT_EQ(alone.frame_ms, with.frame_ms) << spec;
    EXPECT_EQ(alone.efficiency, with.efficiency) << spec;
  }
  EXPECT_EQ(shared.built(), 3u);
  const Trace other = flat_trace(3);
  EXPECT_THROW(run_study(other, "queue", c, &shared), std::invalid_argument);
}

}  // namespace sim_study_test
}  // namespace multiray::balance
