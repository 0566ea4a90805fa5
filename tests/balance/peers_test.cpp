// The peers' balancers (peers_*.h) against what their sources say they do: Cycles' 2%
// dead band, first rebalance and wall-time interval; Equalizer's damping and k-d split;
// OSPRay's round-robin tile ownership and its pre-allocated tiles pulled in batches.
// The generic contract and convergence tests cover them too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "balance/peers_cycles.h"
#include "balance/peers_equalizer.h"
#include "balance/peers_ospray.h"
#include "partition/coverage.h"
#include "partition/tiles.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace peers_test {

using namespace testing;

const FrameShape kShape{640, 360, 1, {}};

// One frame: plan, simulate, update. Returns the frame.
SimFrame step(Balancer& b, const FrameShape& shape, const std::vector<double>& speeds, int frame,
              const CostFn& cost) {
  SimFrame f;
  f.plan = b.plan(shape, frame);
  f.stats = simulate(f.plan, shape, devices_with_speeds(speeds), cost, frame);
  b.update(f.stats);
  return f;
}

// ---------------------------------------------------------------------------- cycles

TEST(Cycles, SlicesRowsLikeCycles) {
  // max(1, round(h·w)) rows each in device order, the last positive weight takes the rest.
  auto s = cycles_slices(7, 10, {0.34, 0.33, 0.33});
  EXPECT_EQ(s[0], (Rect{0, 0, 7, 3}));
  EXPECT_EQ(s[1], (Rect{0, 3, 7, 6}));
  EXPECT_EQ(s[2], (Rect{0, 6, 7, 10}));
  // A tiny weight still gets a row; a weight of 0 (a dropped device) gets none.
  s = cycles_slices(7, 20, {0.9, 0.01, 0.09, 0.0});
  EXPECT_EQ(s[0], (Rect{0, 0, 7, 18}));
  EXPECT_EQ(s[1], (Rect{0, 18, 7, 19}));
  EXPECT_EQ(s[2], (Rect{0, 19, 7, 20}));
  EXPECT_TRUE(s[3].empty());
  // More devices than rows: the first take a row each, the others nothing.
  s = cycles_slices(3, 2, std::vector<double>(5, 0.2));
  std::vector<WorkItem> items;
  for (const Rect& r : s) items.push_back(WorkItem{r, 0});
  EXPECT_EQ(coverage_error(items, 3, 2, 1), "");
  EXPECT_EQ(s[0].height() + s[1].height(), 2);
}

TEST(Cycles, FirstFrameRebalancesAndA31PairConverges) {
  CyclesBalancer b(2);
  EXPECT_EQ(b.plan(kShape, 0).ratios[0], 0.5);  // equal weights first
  step(b, kShape, {3, 1}, 0, flat_cost(kShape));
  // Cycles' first rebalance, from the first frame's times (1/6 and 1/2 of the work):
  // targets 1/4 and 5/12, weights 0.5·1.5 and 0.5·5/6, renormalised to 9/14 and 5/14.
  EXPECT_NEAR(b.weights()[0], 9.0 / 14, 1e-3);
  EXPECT_EQ(b.rebalances_requested(), 1);
  std::vector<SimFrame> run;
  for (int f = 1; f < 12; ++f) run.push_back(step(b, kShape, {3, 1}, f, flat_cost(kShape)));
  // Each changed rebalance is followed up at the next frame until inside the dead band:
  // 0.643, 0.700, 0.726, 0.738, then stop (times 4% apart, targets 1.6% off the mean).
  EXPECT_EQ(b.rebalances_changed(), 4);
  EXPECT_NEAR(b.weights()[0], 0.738, 0.003);
  EXPECT_LT(imbalance(run.back().stats), 0.035);
  EXPECT_GT(imbalance(run.back().stats), 0.02);  // Cycles' dead band, not 0
}

// For two devices the target is halfway to the mean, so it is 2% off the mean when the
// time is 4% off. Speeds 1.08 : 1 put the times 3.85% off the mean (targets 1.92%):
// inside the dead band. 1.09 : 1 puts them 4.3% off (targets 2.15%): outside. A band of
// 2% on the times themselves would already move at 1.08.
TEST(Cycles, TwoPercentDeadBandOnTheTarget) {
  for (const auto& [fast, moves] :
       std::vector<std::pair<double, bool>>{{1.08, false}, {1.09, true}}) {
    CyclesBalancer b(2, 0);  // consider a rebalance after every frame
    for (int f = 0; f < 10; ++f) step(b, kShape, {fast, 1}, f, flat_cost(kShape));
    EXPECT_EQ(b.rebalances_requested(), 10) << fast;
    if (moves) {
      EXPECT_GT(b.rebalances_changed(), 0) << fast;
      EXPECT_GT(b.weights()[0], 0.505) << fast;
    } else {
      EXPECT_EQ(b.rebalances_changed(), 0) << fast;
      EXPECT_EQ(b.weights()[0], 0.5) << fast;
    }
  }
}

// Once balanced, Cycles looks again only after interval_ms of measured time: a device
// that slows down is not followed within the interval, then is followed frame by frame.
TEST(Cycles, NoChangeWithinTheInterval) {
  CyclesBalancer b(2);  // 1000 ms, Cycles' kRebalanceIntervalInSeconds
  double clock = 0, last_request = 0;
  int requests = 0;
  auto frame = [&](const std::vector<double>& speeds, int f) {
    const std::vector<double> before = b.weights();
    const SimFrame sf = step(b, kShape, speeds, f, flat_cost(kShape));
    clock += frame_time_ms(sf.stats);
    if (b.rebalances_requested() == requests) {
      EXPECT_EQ(b.weights(), before) << "frame " << f << ": changed without a rebalance";
    } else {
      requests = b.rebalances_requested();
      last_request = clock;
    }
    return sf;
  };
  int f = 0;
  for (; f < 12; ++f) frame({3, 1}, f);
  const int changes = b.rebalances_changed();
  const double converged = b.weights()[0];
  ASSERT_NEAR(converged, 0.74, 0.01);
  // Device 0 halves its speed. Nothing may change for interval_ms after the last request.
  const double quiet_since = last_request;
  int imbalanced_frames = 0;
  for (; b.rebalances_changed() == changes; ++f) {
    ASSERT_LT(f, 100) << "never rebalanced";
    const SimFrame sf = frame({1.5, 1}, f);
    if (b.rebalances_changed() == changes) {
      EXPECT_EQ(b.weights()[0], converged);
      imbalanced_frames += imbalance(sf.stats) > 0.2 ? 1 : 0;
    }
  }
  EXPECT_GT(clock - quiet_since, 1000.0);  // the change came after the interval ...
  EXPECT_GE(imbalanced_frames, 4);         // ... after frames of ~110 ms 30% imbalanced
  // Then every changed rebalance is followed up at once, back into the dead band.
  for (const int end = f + 12; f < end; ++f) frame({1.5, 1}, f);
  EXPECT_NEAR(b.weights()[0], 0.6, 0.02);
  const SimFrame last = frame({1.5, 1}, f);
  EXPECT_LT(imbalance(last.stats), 0.045);
}

TEST(Cycles, ShorterIntervalFollowsSooner) {
  auto frames_to_recover = [](const std::string& spec) {
    const auto b = make_balancer(spec, 2);
    const auto run =
        simulate_run(*b, kShape, speed_step({3, 1}, {1.5, 1}, 20), flat_cost(kShape), 80);
    return settles_at(run, 20, 0.05) - 20;
  };
  const int fast = frames_to_recover("cycles:interval_ms=100");
  const int slow = frames_to_recover("cycles:interval_ms=2000");
  EXPECT_GE(fast, 0);
  EXPECT_LE(fast, 6) << "slow " << slow;
  EXPECT_GT(slow, 10) << "fast " << fast;  // up to 2 s of 60–110 ms frames before it looks
}

TEST(Cycles, DroppedDeviceRestartsTheMeasurement) {
  CyclesBalancer b(3);
  for (int f = 0; f < 10; ++f) step(b, kShape, {3, 2, 1}, f, flat_cost(kShape));
  const double w0 = b.weights()[0], w2 = b.weights()[2];
  b.drop_device(1);
  EXPECT_EQ(b.weights()[1], 0.0);
  EXPECT_NEAR(b.weights()[0] / b.weights()[2], w0 / w2, 1e-9);  // shares kept in proportion
  const int requested = b.rebalances_requested();
  step(b, kShape, {3, 2, 1}, 10, flat_cost(kShape));
  EXPECT_EQ(b.rebalances_requested(), requested + 1);  // looks at once, as after a reset
}

// ------------------------------------------------------------------------- equalizer

// With flat cost a 640×360 pair is cut into columns at c: the load of each side is its
// time spread evenly over its rectangle, so the undamped cut is where the walk from the
// left reaches half of the total time, and the new cut is (1 − d)·that + d·previous.
TEST(Equalizer, CutIsDampedTowardThePreviousOne) {
  for (double damping : {0.0, 0.5, 0.8}) {
    EqualizerBalancer b(2, damping);
    ASSERT_TRUE(b.tree()[0].left >= 0);
    for (int f = 0; f < 8; ++f) {
      const Plan p = b.plan(kShape, f);
      ASSERT_TRUE(b.cuts_columns(0));  // 640 > 360: the root cuts columns
      const double previous = b.cut(0, 0);
      const FrameStats s = simulate(p, kShape, devices_with_speeds({3, 1}), flat_cost(kShape));
      b.update(s);
      const double c = p.assigned[0][0].rect.x1 / 640.0;  // cut as rendered (whole pixels)
      const double t0 = s.devices[0].time_ms, t1 = s.devices[1].time_ms;
      const double half = (t0 + t1) / 2;
      const double want = half <= t0 ? c * half / t0 : c + (1 - c) * (half - t0) / t1;
      EXPECT_NEAR(b.cut(0, 0), (1 - damping) * want + damping * previous, 1e-9)
          << "damping " << damping << " frame " << f;
    }
  }
}

TEST(Equalizer, DampingHalvesTheStep) {
  // Balanced cut at 0.75; from 0.5, the undamped cut is 0.5 + c/3 (density of device 0
  // is 1/3 of device 1's), so with damping 0.5 the error shrinks by 2/3 per frame and
  // without damping by 1/3.
  for (const auto& [damping, shrink] :
       std::vector<std::pair<double, double>>{{0.5, 2.0 / 3}, {0.0, 1.0 / 3}}) {
    EqualizerBalancer b(2, damping);
    double error = 0.25;
    for (int f = 0; f < 4; ++f) {
      step(b, kShape, {3, 1}, f, flat_cost(kShape));
      const double e = 0.75 - b.cut(0, 0);
      EXPECT_NEAR(e / error, shrink, 0.01) << "damping " << damping << " frame " << f;
      error = e;
    }
  }
}

TEST(Equalizer, KdSplitGivesOneRectanglePerDevicePerView) {
  const FrameShape shape{640, 360, 2, {}};
  for (int n : {2, 3, 4, 5, 7, 8}) {
    EqualizerBalancer b(n);
    std::vector<double> speeds;
    for (int i = 0; i < n; ++i) speeds.push_back(1.0 + (i * 7) % 5);
    Plan p;
    for (int f = 0; f < 6; ++f) p = step(b, shape, speeds, f, uneven_cost(shape)).plan;
    ASSERT_EQ(check_plan(p, shape, n), "") << n;
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(p.assigned[size_t(i)].size(), 2u) << n << " devices, device " << i;
      EXPECT_EQ(p.assigned[size_t(i)][0].view, 0);
      EXPECT_EQ(p.assigned[size_t(i)][1].view, 1);
    }
    EXPECT_TRUE(p.shared.empty());
    EXPECT_FALSE(p.steal);
  }
}

TEST(Equalizer, TreeAlternatesAxes) {
  // Four devices on 640×360: the root cuts columns (left: devices 0–1), each half of
  // 320×360 is higher than wide and cuts rows. So devices 0 and 1 stack in one column.
  EqualizerBalancer b(4);
  Plan p;
  for (int f = 0; f < 5; ++f) p = step(b, kShape, {4, 1, 2, 3}, f, flat_cost(kShape)).plan;
  const Rect r0 = p.assigned[0][0].rect, r1 = p.assigned[1][0].rect;
  const Rect r2 = p.assigned[2][0].rect, r3 = p.assigned[3][0].rect;
  EXPECT_EQ(r0.x0, 0);
  EXPECT_EQ(r0.x1, r1.x1);
  EXPECT_EQ(r0.y1, r1.y0);
  EXPECT_EQ(r2.x0, r0.x1);
  EXPECT_EQ(r2.x1, 640);
  EXPECT_EQ(r2.y1, r3.y0);
  EXPECT_NE(r0.y1, r2.y1);  // each column has its own row cut
  EXPECT_TRUE(b.cuts_columns(0));
  EXPECT_FALSE(b.cuts_columns(b.tree()[0].left));
  EXPECT_FALSE(b.cuts_columns(b.tree()[0].right));
}

TEST(Equalizer, FollowsUnevenCostOnEqualDevices) {
  // The ripple along x makes one half of the columns dearer: the cut leaves the middle.
  const auto b = make_balancer("equalizer", 2);
  const auto run = simulate_run(*b, kShape, constant({1, 1}), uneven_cost(kShape), 25);
  EXPECT_GT(imbalance(run[0].stats), 0.2);
  EXPECT_LT(mean_imbalance(run, 15, 25), 0.01);
  EXPECT_GT(std::abs(run.back().plan.assigned[0][0].rect.x1 - 320), 20);
}

// ---------------------------------------------------------------------------- ospray

TEST(OsprayStatic, TilesAreOwnedRoundRobin) {
  const FrameShape shape{250, 130, 2, {}};  // 4×3 tiles of 64 px per view, 24 in all
  OsprayStaticBalancer b(3);
  const Plan p = b.plan(shape, 0);
  EXPECT_EQ(check_plan(p, shape, 3), "");
  EXPECT_TRUE(p.shared.empty());
  EXPECT_FALSE(p.steal);
  const std::vector<Rect> tiles = make_tiles(250, 130, 64);
  ASSERT_EQ(tiles.size(), 12u);
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(p.assigned[size_t(i)].size(), 8u);
    for (size_t k = 0; k < 8; ++k) {
      const size_t t = k * 3 + size_t(i);  // OSPRay: tileID = taskIndex·N + rank
      EXPECT_EQ(p.assigned[size_t(i)][k], (WorkItem{tiles[t % 12], int(t / 12)}))
          << "device " << i << " task " << k;
    }
  }
  double sum = 0;
  for (double r : p.ratios) sum += r;
  EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST(OsprayStatic, DroppedDeviceLeavesTheRoundRobin) {
  const FrameShape shape{256, 128, 1, {}};  // 8 tiles
  OsprayStaticBalancer b(3, 64);
  b.drop_device(1);
  const Plan p = b.plan(shape, 0);
  EXPECT_EQ(check_plan(p, shape, 3), "");
  EXPECT_TRUE(p.assigned[1].empty());
  const std::vector<Rect> tiles = make_tiles(256, 128, 64);
  for (size_t t = 0; t < tiles.size(); ++t) {
    const auto& own = p.assigned[t % 2 == 0 ? 0 : 2];
    EXPECT_EQ(own[t / 2].rect, tiles[t]) << t;
  }
}

TEST(OsprayStatic, NeverAdapts) {
  const auto b = make_balancer("ospray-static", 2);
  const auto run = simulate_run(*b, kShape, constant({3, 1}), flat_cost(kShape), 6);
  for (const SimFrame& f : run) {
    EXPECT_EQ(f.plan.assigned[0], run[0].plan.assigned[0]);
    EXPECT_GT(imbalance(f.stats), 0.45);  // 3:1 on even halves: 1/6 against 1/2
  }
}

TEST(OsprayDynamic, PreallocatesOwnTilesThenSharesTheRestInBatches) {
  const FrameShape shape{640, 360, 1, {}};  // 10×6 tiles
  OsprayDynamicBalancer b(3, 64, 4);
  const Plan p = b.plan(shape, 0);
  EXPECT_EQ(check_plan(p, shape, 3), "");
  EXPECT_EQ(p.batch, 4);
  EXPECT_FALSE(p.steal);
  const std::vector<Rect> tiles = make_tiles(640, 360, 64);
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(p.assigned[size_t(i)].size(), 4u);
    for (size_t k = 0; k < 4; ++k)
      EXPECT_EQ(p.assigned[size_t(i)][k].rect, tiles[k * 3 + size_t(i)]);
  }
  ASSERT_EQ(p.shared.size(), 60u - 12u);
  EXPECT_EQ(p.shared[0].rect, tiles[12]);  // the rest in scanline order
  EXPECT_EQ(p.shared.back().rect, tiles[59]);
}

// In the simulator a device takes the shared queue `prefetch` tiles per pull: the shared
// items it rendered come in runs of consecutive queue positions whose lengths are
// multiples of the batch, except the run that empties the queue.
TEST(OsprayDynamic, DevicesPullWholeBatches) {
  for (int prefetch : {1, 2, 3, 5}) {
    OsprayDynamicBalancer b(3, 32, prefetch);
    const Plan p = b.plan(kShape, 0);
    const FrameStats s = simulate(p, kShape, devices_with_speeds({3, 2, 1}), flat_cost(kShape));
    const uint32_t first_shared = uint32_t(3 * prefetch);
    const uint32_t end = first_shared + uint32_t(p.shared.size());
    int pulls = 0;
    for (const DeviceFrameStats& d : s.devices) {
      std::vector<uint32_t> ids;
      for (const ItemReport& r : d.items)
        if (r.id >= first_shared) ids.push_back(r.id);
      for (size_t k = 0; k < ids.size();) {
        size_t run = 1;
        while (k + run < ids.size() && ids[k + run] == ids[k] + run) ++run;
        if (ids[k] + run != end) {
          EXPECT_EQ(run % size_t(prefetch), 0u) << "prefetch " << prefetch;
        }
        pulls += int((run + size_t(prefetch) - 1) / size_t(prefetch));
        k += run;
      }
    }
    EXPECT_LE(pulls, int(p.shared.size() + size_t(prefetch) - 1) / prefetch + 3);
    // Every tile rendered once: the queue is emptied.
    double pixels = 0;
    for (const DeviceFrameStats& d : s.devices) pixels += d.pixels;
    EXPECT_EQ(pixels, 640.0 * 360.0);
  }
}

TEST(OsprayDynamic, PrefetchHidesTheRoundTrip) {
  // Behind a 1 ms link every pull costs 2 ms of waiting: 4 tiles per pull save most of it.
  SimLink link;
  link.latency_ms = 1;
  auto frame_ms = [&](const std::string& spec) {
    const auto b = make_balancer(spec, 2);
    const auto run = simulate_run(*b, kShape, constant({3, 1}), flat_cost(kShape), 3, 0, link);
    return run.back().frame_ms;
  };
  const double one = frame_ms("ospray-dynamic:tile=32:prefetch=1");
  const double four = frame_ms("ospray-dynamic:tile=32:prefetch=4");
  EXPECT_LT(four, 0.9 * one);
}

TEST(Peers, SpecsListEveryParameter) {
  EXPECT_EQ(make_balancer("cycles", 2)->spec(), "cycles:interval_ms=1000");
  EXPECT_EQ(make_balancer("cycles:interval_ms=250", 2)->spec(), "cycles:interval_ms=250");
  EXPECT_EQ(make_balancer("equalizer", 2)->spec(), "equalizer:damping=0.5");
  EXPECT_EQ(make_balancer("ospray-static", 2)->spec(), "ospray-static:tile=64");
  EXPECT_EQ(make_balancer("ospray-dynamic:tile=32", 2)->spec(),
            "ospray-dynamic:tile=32:prefetch=4");
  for (const char* bad : {"cycles:interval_ms=-1", "equalizer:damping=1.5",
                          "ospray-static:prefetch=2", "ospray-dynamic:prefetch=0"})
    EXPECT_THROW(make_balancer(bad, 2), std::invalid_argument) << bad;
}

}  // namespace peers_test
}  // namespace multiray::balance
