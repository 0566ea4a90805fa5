// The strongest invariant: the image does not depend on how the work was split.
#include <gtest/gtest.h>

#include <cstring>

#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace split_test {

bool bit_identical(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

class SplitIndependence : public ::testing::Test {
 protected:
  static constexpr int kW = 61, kH = 37;  // odd sizes so regions are uneven
  Scene scene_ = make_cornell_box();
  RenderSettings settings_{.spp = 2, .max_bounces = 8};
  Framebuffer reference_ = testing::render_regions(scene_, kW, kH, settings_, {{0, 0, kW, kH}});
};

TEST_F(SplitIndependence, TwoRegions) {
  const auto fb =
      testing::render_regions(scene_, kW, kH, settings_, {{0, 0, kW, 20}, {0, 20, kW, kH}});
  EXPECT_TRUE(bit_identical(reference_, fb));
}

TEST_F(SplitIndependence, SevenIrregularRegionsOnThreeDevices) {
  const std::vector<Rect> regions{{0, 0, 13, 37},  {13, 0, 61, 5},  {13, 5, 40, 6}, {40, 5, 61, 6},
                                  {13, 6, 14, 37}, {14, 6, 50, 37}, {50, 6, 61, 37}};
  const auto fb = testing::render_regions(scene_, kW, kH, settings_, regions, 3, 1);
  EXPECT_TRUE(bit_identical(reference_, fb));
}

TEST_F(SplitIndependence, MultiThreadedDeviceMatchesSingleThreaded) {
  const auto fb = testing::render_regions(scene_, kW, kH, settings_, {{0, 0, kW, kH}}, 1, 2);
  EXPECT_TRUE(bit_identical(reference_, fb));
}

// The check itself can fail: another frame number gives other random numbers.
TEST_F(SplitIndependence, DifferentFrameGivesDifferentImage) {
  const auto fb = testing::render_regions(scene_, kW, kH, settings_, {{0, 0, kW, kH}}, 1, 1, 1);
  EXPECT_FALSE(bit_identical(reference_, fb));
}

}  // namespace split_test
}  // namespace multiray
