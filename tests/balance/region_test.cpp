// RegionBalancer: any balancer splitting a part of a frame (Harada's machine -> device
// hierarchy), checked on the simulator.
#include <gtest/gtest.h>

#include "balance/region.h"
#include "balance/simulate.h"
#include "partition/coverage.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace {

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

}  // namespace
}  // namespace multiray::balance
