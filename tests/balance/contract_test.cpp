// The Balancer contract, checked for every balancer: plans cover every pixel exactly once
// for any device count and shape (multiview, weighted, tiny, prime); garbage measurements
// never yield NaN ratios; dropped devices get nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "balance/balancer.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace contract_test {

using testing::constant;
using testing::flat_cost;

const std::vector<std::string> kSpecs = {
    "uniform",
    "uniform:layout=columns",
    "uniform:layout=strips",
    "uniform:layout=views",
    "static",
    "queue",
    "queue:tile=7:batch=3",
    "semi-static",
    "dlb",
    "dlb:bits=3",
    "dlb:layout=views",
    "hybrid",
    "hybrid:bands=1:steal=0",
    "hybrid:leave=0",
    "subset",
    "subset:devices=0",
    "hybrid:bands=3:taper=0.9:min_chunk=1",
    "bruder",
    "bruder:zeta=1:tile=5:steal=1",
    "bruder:tile=1:items=tiles",
    "bruder:items=rect",
    "auto",  // runs uniform on one device, hybrid on more
    // The peers' balancers (peers_*.h).
    "cycles",
    "cycles:interval_ms=0",
    "equalizer",
    "equalizer:damping=0",
    "ospray-static",
    "ospray-static:tile=7",
    "ospray-dynamic",
    "ospray-dynamic:tile=7:prefetch=3",
};

std::vector<FrameShape> shapes() {
  FrameShape weighted{64, 48, 2, {}};
  std::mt19937 rng(1);
  for (int i = 0; i < 64 * 48 * 2; ++i) weighted.pixel_weight.push_back(float(rng() % 6));
  return {FrameShape{1, 1, 1, {}},     FrameShape{7, 1, 1, {}},   FrameShape{1, 13, 1, {}},
          FrameShape{641, 359, 1, {}}, FrameShape{40, 30, 9, {}}, weighted};
}

void expect_sane(const Plan& plan, const FrameShape& shape, int devices, const std::string& what) {
  ASSERT_EQ(check_plan(plan, shape, devices), "") << what;
}

class Contract : public ::testing::TestWithParam<std::string> {};

TEST_P(Contract, PlansCoverEveryPixelOnce) {
  for (int devices : {1, 2, 3, 7, 64})
    for (const FrameShape& shape : shapes()) {
      const auto b = make_balancer(GetParam(), devices);
      std::vector<double> speeds(static_cast<size_t>(devices));
      for (int i = 0; i < devices; ++i) speeds[size_t(i)] = 1.0 + i % 4;
      const auto run = simulate_run(*b, shape, constant(speeds), flat_cost(shape), 3);
      for (const SimFrame& f : run)
        expect_sane(f.plan, shape, devices,
                    GetParam() + " " + std::to_string(shape.width) + "x" +
                        std::to_string(shape.height) + "x" + std::to_string(shape.views) + " on " +
                        std::to_string(devices));
    }
}

TEST_P(Contract, GarbageTimingsKeepRatiosFinite) {
  const FrameShape shape{80, 60, 1, {}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto b = make_balancer(GetParam(), 3);
  simulate_run(*b, shape, constant({3, 2, 1}), flat_cost(shape), 6);
  // Unusable everywhere: nothing may change. (dlb only acts on usable frames of its
  // window, so the checks below also cover its deferred update.)
  const std::vector<std::vector<double>> unusable = {
      {0, 0, 0}, {-1, -5, -3}, {nan, nan, nan}, {inf, inf, inf}, {0, -inf, nan}};
  // Queues report last frame's work done as ratios (ospray-dynamic is a queue too).
  const bool measures_shares =
      GetParam().rfind("queue", 0) == 0 || GetParam().rfind("ospray-dynamic", 0) == 0;
  auto expect_unchanged = [&](const Plan& before, const std::string& what) {
    const Plan p = b->plan(shape, 8);
    expect_sane(p, shape, 3, GetParam() + " " + what);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isfinite(p.ratios[i]));
      if (!measures_shares) {
        EXPECT_NEAR(p.ratios[i], before.ratios[i], 1e-12) << GetParam() << " " << what;
      }
    }
  };
  for (size_t k = 0; k < unusable.size(); ++k) {
    const Plan before = b->plan(shape, 7);
    FrameStats s =
        simulate(before, shape, testing::devices_with_speeds({3, 2, 1}), flat_cost(shape));
    for (size_t i = 0; i < 3; ++i) {
      s.devices[i].time_ms = unusable[k][i];
      for (ItemReport& r : s.devices[i].items) r.time_ms = unusable[k][i];
    }
    b->update(s);
    expect_unchanged(before, "case " + std::to_string(k));
  }
  // Devices that did no work, and empty or foreign-shaped reports.
  const Plan before = b->plan(shape, 8);
  FrameStats empty;
  empty.shape = shape;
  empty.devices.resize(3);
  b->update(empty);
  b->update(FrameStats{});
  FrameStats foreign = empty;
  foreign.shape = FrameShape{3, 3, 2, {1.0f}};  // malformed weights
  foreign.devices[0].items.push_back(ItemReport{WorkItem{Rect{0, 0, 99, 99}, 7}, nan, -1});
  b->update(foreign);
  expect_unchanged(before, "empty reports");

  // Partly usable or extreme but valid: anything may change but must stay sane.
  for (const std::vector<double>& times :
       {std::vector<double>{nan, 10, inf}, {1e300, 1e-300, 5}}) {
    FrameStats s = simulate(b->plan(shape, 9), shape, testing::devices_with_speeds({3, 2, 1}),
                            flat_cost(shape));
    for (size_t i = 0; i < 3; ++i) {
      s.devices[i].time_ms = times[i];
      for (ItemReport& r : s.devices[i].items) r.time_ms = times[i];
    }
    b->update(s);
    const Plan p = b->plan(shape, 10);
    expect_sane(p, shape, 3, GetParam());
  }
}

TEST_P(Contract, DroppedDevicesGetNothing) {
  const FrameShape shape{50, 40, 2, {}};
  const auto b = make_balancer(GetParam(), 4);
  simulate_run(*b, shape, constant({1, 2, 3, 4}), flat_cost(shape), 3);
  b->drop_device(2);
  b->drop_device(2);   // twice is harmless
  b->drop_device(99);  // out of range is ignored
  b->drop_device(-1);
  // A device the stats report dead is dropped too.
  auto d = testing::devices_with_speeds({1, 2, 3, 4});
  d[0].alive = false;
  b->update(simulate(b->plan(shape, 3), shape, d, flat_cost(shape)));
  for (int f = 4; f < 8; ++f) {
    const Plan p = b->plan(shape, f);
    expect_sane(p, shape, 4, GetParam());
    for (int dead : {0, 2}) {
      EXPECT_TRUE(p.assigned[size_t(dead)].empty()) << GetParam();
      EXPECT_EQ(p.ratios[size_t(dead)], 0.0) << GetParam();
    }
    b->update(simulate(p, shape, d, flat_cost(shape), f));
  }
  b->drop_device(1);
  b->drop_device(3);  // nobody left: an empty plan, no crash
  const Plan none = b->plan(shape, 9);
  EXPECT_TRUE(none.all_items().empty());
  for (double r : none.ratios) EXPECT_EQ(r, 0.0);
}

TEST_P(Contract, RejectsInvalidShapes) {
  const auto b = make_balancer(GetParam(), 2);
  EXPECT_THROW(b->plan(FrameShape{-1, 5, 1, {}}, 0), std::invalid_argument);
  EXPECT_THROW(b->plan(FrameShape{4, 4, 0, {}}, 0), std::invalid_argument);
  EXPECT_THROW(b->plan(FrameShape{4, 4, 1, {1.0f, 2.0f}}, 0), std::invalid_argument);
  EXPECT_EQ(check_plan(b->plan(FrameShape{0, 0, 1, {}}, 0), FrameShape{0, 0, 1, {}}, 2), "");
}

// Every registered balancer is in kSpecs, so a new one cannot skip the contract.
TEST(ContractSpecs, CoverEveryRegisteredBalancer) {
  for (const std::string& name : balancer_names())
    EXPECT_NE(std::find(kSpecs.begin(), kSpecs.end(), name), kSpecs.end()) << name;
}

INSTANTIATE_TEST_SUITE_P(AllBalancers, Contract, ::testing::ValuesIn(kSpecs),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string n;
                           for (char c : p.param) n += std::isalnum(c) ? c : '_';
                           return n;
                         });

}  // namespace contract_test
}  // namespace multiray::balance
