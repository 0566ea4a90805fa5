// Harada's semi-static balancer: the update step, the paper's form (last frame's reported
// samples, vertical bands) and multiray's (this frame's sample map, scanline ranges).
#include <gtest/gtest.h>

#include <cstdio>

#include "balance/semi_static.h"
#include "partition/weight_map.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace semi_static_test {

using namespace testing;

const FrameShape kShape{200, 100, 1, {}};

TEST(SemiStatic, OneStepOfHaradasUpdate) {
  // Even split, speeds 3:1: n = (½, ½), p ∝ (3, 1), n* = (¾, ¼);
  // α = 0.4 → n = 0.6·½ + 0.4·¾ = 0.6 for device 0.
  SemiStaticBalancer b(2, {.alpha = 0.4});
  simulate_run(b, kShape, constant({3, 1}), flat_cost(kShape), 1);
  EXPECT_NEAR(b.shares()[0], 0.6, 1e-9);
  SemiStaticBalancer full(2, {.alpha = 1.0});  // α = 1 jumps to the ideal split
  simulate_run(full, kShape, constant({3, 1}), flat_cost(kShape), 1);
  EXPECT_NEAR(full.shares()[0], 0.75, 1e-9);
}

const SemiStaticOptions kOurs{.split = LineAxis::rows, .cdf_from_frame = true};

int64_t area_of(const std::vector<WorkItem>& items) {
  int64_t a = 0;
  for (const WorkItem& it : items) a += it.rect.area();
  return a;
}

// 5 samples per pixel in the left half, 1 in the right.
FrameShape left_heavy() {
  FrameShape shape = kShape;
  shape.pixel_weight.assign(size_t(200 * 100), 1.0f);
  for (int y = 0; y < 100; ++y) std::fill_n(shape.pixel_weight.begin() + y * 200, 100, 5.0f);
  return shape;
}

TEST(SemiStatic, DefaultIsThePapersFormOfVerticalBands) {
  SemiStaticBalancer b(3);
  EXPECT_EQ(b.spec(), "semi-static:alpha=0.4");
  const Plan p = b.plan(FrameShape{90, 40, 2, {}}, 0);
  ASSERT_EQ(check_plan(p, FrameShape{90, 40, 2, {}}, 3), "");
  for (const auto& items : p.assigned)
    for (const WorkItem& it : items) {
      EXPECT_EQ(it.rect.y0, 0);  // whole columns: a third of 180 flat columns is 60
      EXPECT_EQ(it.rect.y1, 40);
    }
  EXPECT_EQ(area_of(p.assigned[0]), 60 * 40);
  ASSERT_EQ(p.assigned[1].size(), 2u);  // columns 60..89 of view 0, 0..29 of view 1
  EXPECT_EQ(p.assigned[1][0].rect, (Rect{60, 0, 90, 40}));
  EXPECT_EQ(p.assigned[1][1].rect, (Rect{0, 0, 30, 40}));
  EXPECT_EQ(p.assigned[1][1].view, 1);
  EXPECT_EQ(SemiStaticBalancer(2, kOurs).spec(), "semi-static:alpha=0.4:split=rows:cdf=frame");
}

// Harada builds the CDF from what the devices reported for the previous frame: this
// frame's map is not looked at (the first frame is split by area), last frame's is.
TEST(SemiStatic, PapersFormSplitsByLastFramesReportedSamples) {
  SemiStaticBalancer b(2);
  const FrameShape shape = left_heavy();
  const Plan first = b.plan(shape, 0);
  ASSERT_EQ(check_plan(first, shape, 2), "");
  EXPECT_EQ(area_of(first.assigned[0]), 100 * 100);  // by area: nothing reported yet
  FrameStats s = simulate(first, shape, devices_with_speeds({1, 1}), uniform_cost(shape, 1e-3));
  s.devices[0].time_ms = s.devices[1].time_ms = 10;  // keep the shares even
  s.devices[0].samples = s.devices[1].samples = 1;
  b.update(s);
  // Half the samples = 60 columns of 5 spp = 140 columns of 1: 30% of the area.
  const Plan next = b.plan(kShape, 1);
  EXPECT_NEAR(double(area_of(next.assigned[0])) / (200 * 100), 0.3, 0.01);
}

TEST(SemiStatic, OursSplitsByTheFramesSamplesNotArea) {
  // Top half 5 samples per pixel, bottom half 1: equal work means device 0 (on top) gets
  // a sixth of the rows... (5·r = 1·(1−r)·… ): it must hold half the samples.
  FrameShape shape = kShape;
  shape.pixel_weight.assign(size_t(200 * 100), 1.0f);
  std::fill(shape.pixel_weight.begin(), shape.pixel_weight.begin() + 200 * 50, 5.0f);
  SemiStaticBalancer b(2, kOurs);
  const Plan p = b.plan(shape, 0);
  ASSERT_EQ(check_plan(p, shape, 2), "");
  const WeightMap w(200, 100, 1, shape.pixel_weight);
  const double s0 = w.sum(p.assigned[0]), s1 = w.sum(p.assigned[1]);
  EXPECT_NEAR(s0, s1, 5.0 + 1e-9);  // within one pixel's weight (pixel-precise cut)
  int64_t a0 = 0;
  for (const WorkItem& it : p.assigned[0]) a0 += it.rect.area();
  EXPECT_NEAR(double(a0) / (200 * 100), 0.3, 0.01);  // 30 rows of 5 spp = 70 rows of 1 spp
}

TEST(SemiStatic, RowsUseLastFramesReportedSampleDensity) {
  // No pixel_weight this time: the devices report 5 samples per pixel on top, 1 below.
  SemiStaticBalancer b(2, {.split = LineAxis::rows});
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

// cut=line (the top of Harada's hierarchy): the same split rounded to whole rows, one band a
// device, each cut at most half a row from the pixel-precision one.
TEST(SemiStatic, WholeLinesRoundThePixelCutsToRows) {
  SemiStaticBalancer pixel(3, {.split = LineAxis::rows});
  SemiStaticBalancer line(3, {.split = LineAxis::rows, .whole_lines = true});
  EXPECT_EQ(line.spec(), "semi-static:alpha=0.4:split=rows:cut=line");
  for (int f = 0; f < 4; ++f) {
    const Plan pp = pixel.plan(kShape, f), pl = line.plan(kShape, f);
    int64_t pixel_before = 0, line_before = 0;  // area of the devices before this one
    for (size_t d = 0; d < 3; ++d) {
      ASSERT_EQ(pl.assigned[d].size(), 1u);
      const Rect& r = pl.assigned[d][0].rect;
      EXPECT_TRUE(r.x0 == 0 && r.x1 == kShape.width);
      EXPECT_EQ(r.y0 * int64_t(kShape.width), line_before);
      EXPECT_LE(std::abs(line_before - pixel_before), kShape.width / 2);
      for (const WorkItem& it : pp.assigned[d]) pixel_before += it.rect.area();
      line_before += r.area();
    }
    // Both learn the same frame, so their shares stay equal and only the rounding differs.
    const FrameStats st =
        simulate(pp, kShape, devices_with_speeds({1, 0.45, 0.2}), flat_cost(kShape));
    pixel.update(st);
    line.update(st);
  }
  EXPECT_LT(line.shares()[2], 0.3);  // it learnt: the slow device's band shrank
}

// Mean deviation once converged, adaptive sampling on 4 unequal synthetic devices, where
// the dense band moves by up to 10 px a frame.
double irregular_deviation(SemiStaticOptions options) {
  FrameShape shape{320, 180, 1, {}};
  SemiStaticBalancer b(4, options);
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
  return dev / 40;
}

TEST(SemiStatic, DeviationWithIrregularSamples) {
  // Issue 4's goal for ours, which splits by the frame's own samples: ≤ 2%.
  const double ours = irregular_deviation(kOurs);
  EXPECT_LT(ours, 0.02);
  // The paper's form splits by last frame's samples, so the band's motion costs it.
  const double paper = irregular_deviation({});
  std::printf("deviation: ours %.4f, paper's form %.4f\n", ours, paper);
  EXPECT_GT(paper, ours);
}

}  // namespace semi_static_test
}  // namespace multiray::balance
