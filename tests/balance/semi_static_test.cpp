// Harada's semi-static balancer: the update step, and the CDF split by samples.
#include <gtest/gtest.h>

#include "balance/semi_static.h"
#include "partition/weight_map.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace {

using namespace testing;

const FrameShape kShape{200, 100, 1, {}};

TEST(SemiStatic, OneStepOfHaradasUpdate) {
  // Even split, speeds 3:1: n = (½, ½), p ∝ (3, 1), n* = (¾, ¼);
  // α = 0.4 → n = 0.6·½ + 0.4·¾ = 0.6 for device 0.
  SemiStaticBalancer b(2, 0.4);
  simulate_run(b, kShape, constant({3, 1}), flat_cost(kShape), 1);
  EXPECT_NEAR(b.shares()[0], 0.6, 1e-9);
  SemiStaticBalancer full(2, 1.0);  // α = 1 jumps to the ideal split
  simulate_run(full, kShape, constant({3, 1}), flat_cost(kShape), 1);
  EXPECT_NEAR(full.shares()[0], 0.75, 1e-9);
}

TEST(SemiStatic, SplitsByTheFramesSamplesNotArea) {
  // Top half 5 samples per pixel, bottom half 1: equal work means device 0 (on top) gets
  // a sixth of the rows... (5·r = 1·(1−r)·… ): it must hold half the samples.
  FrameShape shape = kShape;
  shape.pixel_weight.assign(size_t(200 * 100), 1.0f);
  std::fill(shape.pixel_weight.begin(), shape.pixel_weight.begin() + 200 * 50, 5.0f);
  SemiStaticBalancer b(2);
  const Plan p = b.plan(shape, 0);
  ASSERT_EQ(check_plan(p, shape, 2), "");
  const WeightMap w(200, 100, 1, shape.pixel_weight);
  const double s0 = w.sum(p.assigned[0]), s1 = w.sum(p.assigned[1]);
  EXPECT_NEAR(s0, s1, 5.0 + 1e-9);  // within one pixel's weight (pixel-precise cut)
  int64_t a0 = 0;
  for (const WorkItem& it : p.assigned[0]) a0 += it.rect.area();
  EXPECT_NEAR(double(a0) / (200 * 100), 0.3, 0.01);  // 30 rows of 5 spp = 70 rows of 1 spp
}

TEST(SemiStatic, UsesLastFramesReportedSampleDensity) {
  // No pixel_weight this time: the devices report 5 samples per pixel on top, 1 below.
  SemiStaticBalancer b(2);
  FrameShape reported = kShape;
  reported.pixel_weight.assign(size_t(200 * 100), 1.0f);
  std::fill(reported.pixel_weight.begin(), reported.pixel_weight.begin() + 200 * 50, 5.0f);
  FrameStats s = simulate(b.plan(kShape, 0), reported, devices_with_speeds({1, 1}),
                          uniform_cost(reported, 1e-3));
  s.devices[0].time_ms = s.devices[1].time_ms = 10;  // keep the shares even
  s.devices[0].samples = s.devices[1].samples = 1;
  b.update(s);
  const Plan p = b.plan(kShape, 1);
  int64_t a0 = 0;
  for (const WorkItem& it : p.assigned[0]) a0 += it.rect.area();
  EXPECT_NEAR(double(a0) / (200 * 100), 0.3, 0.01);
}

TEST(SemiStatic, DeviationWithIrregularSamples) {
  // Issue 4's goal on synthetic devices: adaptive sampling on 4 unequal devices, mean
  // deviation ≤ 2% once converged.
  FrameShape shape{320, 180, 1, {}};
  SemiStaticBalancer b(4);
  double dev = 0;
  for (int f = 0; f < 60; ++f) {
    shape.pixel_weight.assign(size_t(320 * 180), 1.0f);
    for (int y = 0; y < 180; ++y)
      for (int x = 0; x < 320; ++x)
        if (std::abs(x - 160 - 100 * std::sin(f * 0.1) - 0.5 * y) < 20)
          shape.pixel_weight[size_t(y * 320 + x)] = 5;
    const FrameStats s = simulate(b.plan(shape, f), shape, devices_with_speeds({4, 3, 2, 1}, 0.01),
                                  uniform_cost(shape, 1e-3), f, 5);
    b.update(s);
    if (f >= 20) dev += deviation(s);
  }
  EXPECT_LT(dev / 40, 0.02);
}

}  // namespace
}  // namespace multiray::balance
