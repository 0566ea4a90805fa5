// The `bruder` balancer (Bruder, Frey & Ertl 2017, §6.2): the k-d split of a tile cost
// grid, the shares from costs per unit of work, and the balancer on the simulator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "balance/bruder.h"
#include "partition/kd_tiles.h"
#include "partition/weight_map.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace bruder_test {

using testing::constant;
using testing::devices_with_speeds;

// A w×h grid of tiles with a hot spot (cost up to 41) off centre over a base cost of 1.
TileCosts hot_spot(int w, int h) {
  TileCosts g{w, h, {}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dx = x - 0.3 * w, dy = y - 0.6 * h;
      g.cost.push_back(1 + 40 * std::exp(-(dx * dx + dy * dy) / (0.05 * (w * w + h * h))));
    }
  return g;
}

std::vector<double> uneven_shares(int n) {
  std::vector<double> s;
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += s.emplace_back(1.0 + (i * 7) % 3);
  for (double& x : s) x /= sum;
  return s;
}

// How many rectangles hold each tile; every rect must lie inside the grid.
std::vector<int> cover_counts(const TileCosts& g, const std::vector<Rect>& rects) {
  std::vector<int> count(g.cost.size(), 0);
  for (const Rect& r : rects) {
    if (r.empty()) continue;
    EXPECT_TRUE(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= g.width && r.y1 <= g.height);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) ++count[size_t(y * g.width + x)];
  }
  return count;
}

double cost_of(const TileCosts& g, const Rect& r) {
  double c = 0;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) c += g.cost[size_t(y * g.width + x)];
  return c;
}

TEST(KdTiles, CoversEveryTileOnceAndMatchesShares) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{
           {1, 1}, {7, 1}, {1, 13}, {13, 9}, {41, 29}, {97, 61}, {240, 135}})
    for (int n = 1; n <= 7; ++n) {
      const TileCosts g = hot_spot(w, h);
      const std::vector<double> shares = uneven_shares(n);
      const std::vector<Rect> rects = kd_split_tiles(g, shares);
      ASSERT_EQ(rects.size(), size_t(n));
      for (int c : cover_counts(g, rects)) ASSERT_EQ(c, 1) << w << "x" << h << " on " << n;
      // Each cut misses by at most half a row or column of tiles; a device lies below
      // ceil(log2 n) cuts.
      double total = 0, slab = 0;
      for (double c : g.cost) total += c;
      for (int x = 0; x < w; ++x) slab = std::max(slab, cost_of(g, Rect{x, 0, x + 1, h}));
      for (int y = 0; y < h; ++y) slab = std::max(slab, cost_of(g, Rect{0, y, w, y + 1}));
      const double tolerance = std::ceil(std::log2(n)) * slab / 2 / total + 1e-12;
      if (w * h > 30000) {
        EXPECT_LT(tolerance, 0.025);  // a 1920×1080 frame in 8×8 tiles
      }
      for (int i = 0; i < n; ++i)
        EXPECT_NEAR(cost_of(g, rects[size_t(i)]) / total, shares[size_t(i)], tolerance)
            << w << "x" << h << " device " << i << " of " << n;
    }
}

TEST(KdTiles, CutsTheLongerSideFirst) {
  const std::vector<Rect> wide =
      kd_split_tiles(TileCosts{10, 4, std::vector<double>(40, 1)}, {0.5, 0.5});
  EXPECT_EQ(wide[0], (Rect{0, 0, 5, 4}));
  EXPECT_EQ(wide[1], (Rect{5, 0, 10, 4}));
  const std::vector<Rect> tall =
      kd_split_tiles(TileCosts{4, 10, std::vector<double>(40, 1)}, {0.3, 0.7});
  EXPECT_EQ(tall[0], (Rect{0, 0, 4, 3}));
  EXPECT_EQ(tall[1], (Rect{0, 3, 4, 10}));
}

TEST(KdTiles, ZeroSharesGetNothingAndFreeGridsSplitByArea) {
  const TileCosts g = hot_spot(20, 10);
  const std::vector<Rect> r = kd_split_tiles(g, {0.0, 0.5, 0.0, 0.5, 0.0});
  for (int i : {0, 2, 4}) EXPECT_TRUE(r[size_t(i)].empty()) << i;
  for (int c : cover_counts(g, r)) ASSERT_EQ(c, 1);
  // Costs all 0 (or garbage): tile counts are split instead.
  TileCosts free{20, 10, std::vector<double>(200, 0.0)};
  free.cost[3] = -5;
  free.cost[4] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Rect> f = kd_split_tiles(free, {0.25, 0.75});
  EXPECT_EQ(f[0].area(), 50);
  // No positive share: all count as equal.
  EXPECT_EQ(kd_split_tiles(free, {0.0, -1.0})[0].area(), 100);
}

TEST(KdTiles, RejectsBadInput) {
  EXPECT_THROW(kd_split_tiles(TileCosts{2, 2, {1, 1, 1, 1}}, {}), std::invalid_argument);
  EXPECT_THROW(kd_split_tiles(TileCosts{2, 2, {1, 1, 1}}, {1}), std::invalid_argument);
  EXPECT_THROW(kd_split_tiles(TileCosts{-1, 2, {}}, {1}), std::invalid_argument);
  EXPECT_EQ(kd_split_tiles(TileCosts{0, 0, {}}, {1, 1})[1].area(), 0);
}

TEST(BruderShares, InverseCostDampedTowardUniform) {
  std::vector<double> r = prediction_shares({1, 2.5}, 1.0);
  EXPECT_NEAR(r[0], 1 / 1.4, 1e-12);  // 0.714
  EXPECT_NEAR(r[1], 0.4 / 1.4, 1e-12);
  r = prediction_shares({1, 2.5}, 0.5);
  EXPECT_NEAR(r[0], 0.5 / 1.4 + 0.25, 1e-12);  // 0.607
  EXPECT_NEAR(r[1], 0.2 / 1.4 + 0.25, 1e-12);  // 0.393
  // Three devices: Eq. 3 as printed would not sum to 1 here; 1/σ normalised does.
  r = prediction_shares({1, 2, 4}, 1.0);
  EXPECT_NEAR(r[0] + r[1] + r[2], 1.0, 1e-12);
  EXPECT_NEAR(r[0], 4.0 / 7, 1e-12);
  EXPECT_NEAR(r[2], 1.0 / 7, 1e-12);
  EXPECT_NEAR(prediction_shares({1, 2, 4}, 0.0)[2], 1.0 / 3, 1e-12);
}

TEST(BruderShares, ZetaWeighsThePredictionAsEq3PrintsIt) {
  // ζ on the prediction term: at ζ = 0.8 a 1 : 3 cost pair gets 0.8·0.75 + 0.2·0.5 = 0.70.
  // The damping reading, ζ on the uniform term, would give 0.2·0.75 + 0.8·0.5 = 0.55.
  std::vector<double> r = prediction_shares({1, 3}, 0.8);
  EXPECT_NEAR(r[0], 0.70, 1e-12);
  EXPECT_NEAR(r[1], 0.30, 1e-12);
  r = prediction_shares({1, 3}, 0.2);  // mostly uniform
  EXPECT_NEAR(r[0], 0.2 * 0.75 + 0.8 * 0.5, 1e-12);
  // Three devices 1 : 2 : 4 at ζ = 0.8: 0.8·(4, 2, 1)/7 + 0.2/3.
  r = prediction_shares({1, 2, 4}, 0.8);
  EXPECT_NEAR(r[0], 0.8 * 4 / 7 + 0.2 / 3, 1e-12);
  EXPECT_NEAR(r[2], 0.8 * 1 / 7 + 0.2 / 3, 1e-12);
  EXPECT_NEAR(r[0] + r[1] + r[2], 1.0, 1e-12);
}

TEST(BruderShares, UnknownCostsDeadDevicesAndExtremes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Unknown σ: the mean weight of the known ones (1 and 0.5 → 0.75).
  std::vector<double> r = prediction_shares({1, 2, nan}, 1.0);
  EXPECT_NEAR(r[2], 0.75 / 2.25, 1e-12);
  r = prediction_shares({nan, 0, -1}, 0.3);  // nothing known: uniform
  for (double x : r) EXPECT_NEAR(x, 1.0 / 3, 1e-12);
  r = prediction_shares({1, 2, 4}, 0.5, {true, false, true});
  EXPECT_EQ(r[1], 0.0);
  EXPECT_NEAR(r[0] + r[2], 1.0, 1e-12);
  r = prediction_shares({1e-306, 1e300, 1e-306}, 1.0);  // no overflow, no NaN
  EXPECT_NEAR(r[0], 0.5, 1e-12);
  EXPECT_EQ(prediction_shares({1, 1}, 0.5, {false, false}), (std::vector<double>{0, 0}));
  EXPECT_THROW(prediction_shares({1, 1}, 1.5), std::invalid_argument);
  EXPECT_THROW(prediction_shares({1, 1}, 0.5, {true}), std::invalid_argument);
}

BruderBalancer::Options options(double zeta, int tile = 8, bool steal = false,
                                const std::string& items = "rows") {
  BruderBalancer::Options o;
  o.zeta = zeta, o.tile = tile, o.steal = steal, o.items = items;
  return o;
}

// Weights 1..6 with a bright blob, as a volume's predicted samples per pixel.
FrameShape weighted_shape(int w, int h, int views, int seed = 0) {
  FrameShape s{w, h, views, {}, {}};
  std::mt19937 rng(uint32_t(seed + 1));
  for (int v = 0; v < views; ++v)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        s.pixel_weight.push_back(
            float(1 + rng() % 3 + (std::hypot(x - w / 3, y - h / 2) < h / 4 ? 3 : 0)));
  return s;
}

TEST(Bruder, PlansAreValidForManyShapes) {
  std::vector<FrameShape> shapes = {FrameShape{1, 1, 1, {}, {}},   FrameShape{37, 23, 1, {}, {}},
                                    FrameShape{7, 1, 3, {}, {}},   FrameShape{640, 360, 1, {}, {}},
                                    FrameShape{61, 45, 3, {}, {}}, weighted_shape(37, 23, 1),
                                    weighted_shape(61, 45, 3, 1),  FrameShape{0, 0, 1, {}, {}}};
  for (int devices : {1, 2, 3, 5})
    for (int tile : {1, 8, 13})
      for (bool steal : {false, true})
        for (const char* items : {"rect", "rows", "tiles"}) {
          BruderBalancer b(devices, options(0.5, tile, steal, items));
          std::vector<double> speeds;
          for (int i = 0; i < devices; ++i) speeds.push_back(1.0 + i % 3);
          // The size changes every frame, as under image-space resolution tuning.
          for (int f = 0; f < int(shapes.size()) * 2; ++f) {
            const FrameShape& shape = shapes[size_t(f) % shapes.size()];
            const Plan p = b.plan(shape, f);
            ASSERT_EQ(check_plan(p, shape, devices), "")
                << shape.width << "x" << shape.height << "x" << shape.views << " tile " << tile
                << " on " << devices;
            EXPECT_EQ(p.steal, steal && shape.pixels() > 0);
            b.update(
                simulate(p, shape, devices_with_speeds(speeds), testing::flat_cost(shape), f));
          }
        }
}

TEST(Bruder, ItemsAreTilesInRowMajorOrderOfTheDevicesRectangle) {
  const FrameShape shape{61, 45, 3, {}, {}};  // 8 tile columns per view, the last 5 wide
  BruderBalancer b(3, options(0.5, 8, false, "tiles"));
  const Plan p = b.plan(shape, 0);
  for (const std::vector<WorkItem>& items : p.assigned) {
    ASSERT_FALSE(items.empty());
    for (size_t k = 0; k < items.size(); ++k) {
      const Rect& r = items[k].rect;
      EXPECT_TRUE(r.x0 % 8 == 0 && r.y0 % 8 == 0 && r.width() <= 8 && r.height() <= 8);
      if (k == 0) continue;
      const Rect& q = items[k - 1].rect;
      const int tx = items[k].view * 8 + r.x0 / 8, qx = items[k - 1].view * 8 + q.x0 / 8;
      EXPECT_TRUE(r.y0 > q.y0 || (r.y0 == q.y0 && tx == qx + 1)) << k;
    }
  }
}

// Rows and whole rectangles: the same pixels per device as tiles, in far fewer items, each
// within one view.
TEST(Bruder, RowsAndRectsMergeTheTilesOfADevice) {
  const FrameShape shape{61, 45, 3, {}, {}};
  BruderBalancer tiles(3, options(0.5, 8, false, "tiles")),
      rows(3, options(0.5, 8, false, "rows")), rect(3, options(0.5, 8, false, "rect"));
  const Plan pt = tiles.plan(shape, 0), pr = rows.plan(shape, 0), pc = rect.plan(shape, 0);
  for (size_t d = 0; d < 3; ++d) {
    int64_t a = 0, b = 0, c = 0;
    for (const WorkItem& w : pt.assigned[d]) a += w.rect.area();
    for (const WorkItem& w : pr.assigned[d]) b += w.rect.area();
    for (const WorkItem& w : pc.assigned[d]) c += w.rect.area();
    EXPECT_EQ(a, b);
    EXPECT_EQ(a, c);
    EXPECT_LT(pr.assigned[d].size(), pt.assigned[d].size());
    EXPECT_LE(pc.assigned[d].size(), 3u);  // one per view the rectangle spans
    for (const WorkItem& w : pr.assigned[d]) EXPECT_LE(w.rect.height(), 8);
  }
  EXPECT_TRUE(check_plan(pr, shape, 3).empty());
  EXPECT_TRUE(check_plan(pc, shape, 3).empty());
}

TEST(Bruder, SplitsByPredictedDeviceCost) {
  FrameShape shape = weighted_shape(160, 96, 1);
  shape.device_cost = {1e-3, 2.5e-3};
  BruderBalancer b(2, options(1.0));
  const Plan p = b.plan(shape, 0);
  EXPECT_NEAR(p.ratios[0], 1 / 1.4, 1e-9);
  const WeightMap w(shape.width, shape.height, 1, shape.pixel_weight);
  EXPECT_NEAR(w.sum(p.assigned[0]) / w.total(), 1 / 1.4, 0.02);  // tile granularity
  // A prediction that is unusable for one device: its measured σ (none yet: the mean).
  shape.device_cost = {1e-3, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_NEAR(b.plan(shape, 1).ratios[0], 0.5, 1e-12);
}

TEST(Bruder, LearnsCostsFromStatsWithoutPredictions) {
  const FrameShape shape = weighted_shape(160, 96, 1);
  BruderBalancer b(2, options(1.0));
  const auto run = simulate_run(b, shape, constant({1, 0.4}), uniform_cost(shape, 1e-3), 4);
  EXPECT_NEAR(run[0].plan.ratios[0], 0.5, 1e-12);  // the first frame is uniform
  EXPECT_NEAR(b.measured_cost()[0], 1e-3, 1e-9);   // ms per unit of pixel weight
  EXPECT_NEAR(b.measured_cost()[1], 2.5e-3, 1e-9);
  for (int f = 1; f < 4; ++f) {
    EXPECT_NEAR(run[size_t(f)].plan.ratios[0], 1 / 1.4, 1e-6);
    EXPECT_LT(imbalance(run[size_t(f)].stats), 0.03) << f;
  }
}

TEST(Bruder, PapersZetaCostsBalanceAndStealingWinsItBack) {
  // ζ = 0.5 holds 1 : 0.4 at 0.607/0.393 instead of 0.714/0.286: the slow device takes
  // 0.393/0.4 = 0.98 of the fast one's whole-frame time, λ ≈ 0.24 (less or more by the
  // k-d cut's tile granularity). Stealing repairs it.
  const FrameShape shape = weighted_shape(160, 96, 1);
  BruderBalancer paper(2, options(0.5)), ours(2, options(0.5, 8, true));
  const auto a = simulate_run(paper, shape, constant({1, 0.4}), uniform_cost(shape, 1e-3), 6);
  const auto c = simulate_run(ours, shape, constant({1, 0.4}), uniform_cost(shape, 1e-3), 6);
  EXPECT_NEAR(a.back().plan.ratios[0], 0.5 / 1.4 + 0.25, 1e-6);
  const WeightMap w(shape.width, shape.height, 1, shape.pixel_weight);
  const double got = w.sum(a.back().plan.assigned[0]) / w.total();  // 0.621 on 20×12 tiles
  EXPECT_NEAR(got, 0.5 / 1.4 + 0.25, 0.02);
  const double t0 = got, t1 = (1 - got) / 0.4;
  EXPECT_NEAR(imbalance(a.back().stats), 2 * std::max(t0, t1) / (t0 + t1) - 1, 1e-9);
  EXPECT_GT(imbalance(a.back().stats), 0.18);
  EXPECT_TRUE(c.back().plan.steal);
  EXPECT_LT(imbalance(c.back().stats), 0.02);
}

TEST(Bruder, FixedCostsAreThePapersStaticBaseline) {
  // sigma=A/B fixes σ̄ for the run: predictions and measurements are ignored, the k-d
  // tiles still follow the pixel weights.
  FrameShape shape = weighted_shape(160, 96, 1);
  shape.device_cost = {1e-3, 1e-3};  // a prediction that would split evenly
  const auto b = make_balancer("bruder:zeta=1:sigma=1/2.5", 2);
  EXPECT_EQ(b->spec(), "bruder:zeta=1:tile=8:steal=0:items=rows:sigma=1/2.5");
  EXPECT_EQ(make_balancer(b->spec(), 2)->spec(), b->spec());
  for (int f = 0; f < 3; ++f) {
    const Plan p = b->plan(shape, f);
    ASSERT_EQ(check_plan(p, shape, 2), "");
    EXPECT_NEAR(p.ratios[0], 1 / 1.4, 1e-12) << f;  // the first frame too
    const WeightMap w(shape.width, shape.height, 1, shape.pixel_weight);
    EXPECT_NEAR(w.sum(p.assigned[0]) / w.total(), 1 / 1.4, 0.02);
    b->update(simulate(p, shape, devices_with_speeds({1, 1}), uniform_cost(shape, 1e-3), f));
  }
  EXPECT_THROW(make_balancer("bruder:sigma=1/2", 3), std::invalid_argument);
}

TEST(Bruder, KeepsLearningWhileTheImageSizeChanges) {
  BruderBalancer b(2, options(1.0));
  for (int f = 0; f < 8; ++f) {
    const FrameShape shape = weighted_shape(80 + 17 * f, 48 + 9 * (f % 3), 1, f);
    const Plan p = b.plan(shape, f);
    ASSERT_EQ(check_plan(p, shape, 2), "");
    if (f > 0) {
      EXPECT_NEAR(p.ratios[0], 1 / 1.4, 1e-6) << f;
    }
    b.update(simulate(p, shape, devices_with_speeds({1, 0.4}), uniform_cost(shape, 1e-3), f));
  }
}

TEST(Bruder, GarbageUpdatesNeverGiveNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const FrameShape shape = weighted_shape(50, 30, 2);
  BruderBalancer b(3, options(0.5));
  for (double t : {0.0, -1.0, nan, inf, 1e300, 1e-300}) {
    FrameStats s = simulate(b.plan(shape, 0), shape, devices_with_speeds({3, 2, 1}),
                            uniform_cost(shape, 1e-3));
    for (DeviceFrameStats& d : s.devices) d.time_ms = t;
    s.devices[1].items.clear();  // falls back to the planned work
    b.update(s);
    FrameStats missing = s;
    missing.devices.resize(1);
    b.update(missing);
    FrameStats foreign = s;
    foreign.shape = FrameShape{3, 3, 1, {}, {}};
    b.update(foreign);
    const Plan p = b.plan(shape, 1);
    ASSERT_EQ(check_plan(p, shape, 3), "") << t;
  }
  b.drop_device(1);
  const Plan p = b.plan(shape, 2);
  ASSERT_EQ(check_plan(p, shape, 3), "");
  EXPECT_TRUE(p.assigned[1].empty());
  EXPECT_EQ(p.ratios[1], 0.0);
}

TEST(Bruder, SpecRoundTripsAndBadOptionsThrow) {
  const auto b = make_balancer("bruder", 2);
  EXPECT_EQ(b->spec(), "bruder:zeta=0.5:tile=8:steal=0:items=rows");
  EXPECT_EQ(make_balancer(b->spec(), 2)->spec(), b->spec());
  const auto c = make_balancer("bruder:steal=1:tile=16:zeta=1:items=tiles", 3);
  EXPECT_EQ(c->spec(), "bruder:zeta=1:tile=16:steal=1:items=tiles");
  EXPECT_EQ(make_balancer(c->spec(), 3)->spec(), c->spec());
  EXPECT_TRUE(c->plan(FrameShape{40, 30, 1, {}, {}}, 0).steal);
  for (const char* bad : {"bruder:zeta=2", "bruder:zeta=-0.1", "bruder:tile=0", "bruder:tile=4097",
                          "bruder:steal=5", "bruder:tiles=8", "bruder:items=pixels",
                          "bruder:sigma=1", "bruder:sigma=1/0", "bruder:sigma=1/x"})
    EXPECT_THROW(make_balancer(bad, 2), std::invalid_argument) << bad;
}

}  // namespace bruder_test
}  // namespace multiray::balance
