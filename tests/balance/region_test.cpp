// RegionBalancer: any balancer splitting a part of a frame (Harada's machine -> device
// hierarchy), checked on the simulator.
#include <gtest/gtest.h>

#include "balance/region.h"
#include "balance/simulate.h"
#include "partition/coverage.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace region_test {

TEST(Region, CropShapeKeepsTheRegionsWeights) {
  FrameShape s{4, 3, 2, {}};
  for (int i = 0; i < 24; ++i) s.pixel_weight.push_back(float(i));
  const FrameShape c = crop_shape(s, Rect{1, 1, 3, 9});  // clipped to y < 3
  EXPECT_EQ(c.width, 2);
  EXPECT_EQ(c.height, 2);
  EXPECT_EQ(c.pixel_weight, (std::vector<float>{5, 6, 9, 10, 17, 18, 21, 22}));
  EXPECT_THROW(crop_shape(s, Rect{5, 0, 9, 3}), std::invalid_argument);
}

// Two "machines" get a band each (the level above); each splits its band across its two
// devices with its own balancer. Every pixel is covered once per frame, and each machine's
// devices end up finishing together.
TEST(Region, TwoLevelSplitCoversTheFrameAndBalancesEachMachine) {
  const FrameShape shape{96, 64, 1, {}};
  const CostFn cost = testing::uneven_cost(shape);
  const Rect bands[2] = {{0, 0, 96, 40}, {0, 40, 96, 64}};
  const std::vector<SimDevice> devs[2] = {testing::devices_with_speeds({1.0, 0.5}),
                                          testing::devices_with_speeds({0.25, 1.0})};
  for (const char* spec : {"hybrid", "semi-static", "static", "queue:tile=8"}) {
    RegionBalancer machine[2] = {RegionBalancer(make_balancer(spec, 2), bands[0]),
                                 RegionBalancer(make_balancer(spec, 2), bands[1])};
    double last_imbalance[2] = {1, 1};
    for (int frame = 0; frame < 12; ++frame) {
      std::vector<WorkItem> all;
      for (int m = 0; m < 2; ++m) {
        const Plan p = machine[m].plan(shape, frame);
        for (const WorkItem& it : p.all_items()) {
          EXPECT_GE(it.rect.y0, bands[m].y0) << spec;
          EXPECT_LE(it.rect.y1, bands[m].y1) << spec;
          all.push_back(it);
        }
        const FrameStats st = simulate(p, shape, devs[m], cost, frame);
        machine[m].update(st);
        last_imbalance[m] = imbalance(st);
      }
      ASSERT_EQ(coverage_error(all, shape.width, shape.height, shape.views), "") << spec;
    }
    if (std::string(spec) != "static") {  // static keeps its first-frame calibration
      EXPECT_LT(last_imbalance[0], 0.1) << spec;
      EXPECT_LT(last_imbalance[1], 0.1) << spec;
    }
  }
}

TEST(Region, TransposeAndOneViewCropKeepWeights) {
  FrameShape s{3, 2, 2, {}};
  for (int i = 0; i < 12; ++i) s.pixel_weight.push_back(float(i));
  const FrameShape t = transposed(s);
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.height, 3);
  EXPECT_EQ(t.pixel_weight, (std::vector<float>{0, 3, 1, 4, 2, 5, 6, 9, 7, 10, 8, 11}));
  const FrameShape v1 = crop_shape(s, Rect{1, 0, 3, 2}, 1);
  EXPECT_EQ(v1.views, 1);
  EXPECT_EQ(v1.pixel_weight, (std::vector<float>{7, 8, 10, 11}));
  EXPECT_THROW(crop_shape(s, Rect{0, 0, 3, 2}, 2), std::invalid_argument);
}

// Harada's second level: a machine splits its band (here of view 1 only) across its
// devices in the other direction. Every balancer covers exactly the band of that view,
// with items that span the band's full height (columns) for the row-splitting ones.
TEST(Region, TransposedSplitOfOneViewCoversItsBandInColumns) {
  const FrameShape shape{64, 48, 2, {}};
  const Region band{Rect{0, 16, 64, 40}, 1, true};
  for (const std::string& spec : balancer_names()) {
    RegionBalancer machine(make_balancer(spec, 3), band);
    const std::vector<SimDevice> devs = testing::devices_with_speeds({1.0, 0.5, 0.25});
    for (int frame = 0; frame < 4; ++frame) {
      const Plan p = machine.plan(shape, frame);
      std::vector<WorkItem> local;
      for (WorkItem it : p.all_items()) {
        ASSERT_EQ(it.view, 1) << spec;
        ASSERT_GE(it.rect.y0, 16) << spec;
        ASSERT_LE(it.rect.y1, 40) << spec;
        if (spec == "uniform") {
          EXPECT_EQ(it.rect.height(), 24) << spec << ": not a column";
        }
        it.view = 0;
        it.rect = Rect{it.rect.x0, it.rect.y0 - 16, it.rect.x1, it.rect.y1 - 16};
        local.push_back(it);
      }
      ASSERT_EQ(coverage_error(local, 64, 24, 1), "") << spec;
      machine.update(simulate(p, shape, devs, testing::uneven_cost(shape), frame));
    }
  }
}

}  // namespace region_test
}  // namespace multiray::balance
