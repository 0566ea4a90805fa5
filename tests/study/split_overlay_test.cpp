// The picture of a frame's split (study/split_overlay.h): each device's pieces tinted in its
// colour and outlined, the rest of the frame untouched, a legend row per device below.
#include "study/split_overlay.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace multiray::study {
namespace {

Rgb8Image grey(int w, int h, uint8_t v) {
  return Rgb8Image{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 3, v)};
}

const uint8_t* at(const Rgb8Image& im, int x, int y) {
  return &im.rgb[(size_t(y) * size_t(im.width) + size_t(x)) * 3];
}

TEST(SplitOverlay, TintsEachDevicesPiecesAndLeavesTheRest) {
  const Rgb8Image frame = grey(40, 20, 100);
  std::vector<OverlayDevice> devices(2);
  devices[0].name = "cpu";
  devices[0].rects = {Rect{0, 0, 20, 10}};
  devices[0].share = 0.5;
  devices[1].name = "opencl:0";
  devices[1].rects = {Rect{20, 0, 40, 10}, Rect{30, 15, 50, 30}};  // the second clipped
  devices[1].share = 0.5;
  const Rgb8Image out = split_overlay(frame, devices, "frame 0");
  EXPECT_EQ(out.width, 40);
  EXPECT_GT(out.height, 20 + 3 * 12 - 1);  // a title row and a row per device
  uint8_t c0[3], c1[3];
  device_colour(0, c0);
  device_colour(1, c1);
  // Outlines mostly the device's own colour; insides a lighter blend of colour and frame.
  const auto blend = [](int frame_value, int colour, double a) {
    return int(frame_value * (1 - a) + colour * a + 0.5);
  };
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(at(out, 0, 0)[k], blend(100, c0[k], 0.75), 1);
    EXPECT_NEAR(at(out, 20, 5)[k], blend(100, c1[k], 0.75), 1);
    EXPECT_NEAR(at(out, 10, 5)[k], blend(100, c0[k], 0.4), 1);
    EXPECT_NEAR(at(out, 25, 5)[k], blend(100, c1[k], 0.4), 1);
    EXPECT_EQ(at(out, 10, 12)[k], 100);  // no device's piece: untouched
  }
  EXPECT_NE(at(out, 35, 18)[0], 100);  // the clipped piece is drawn where it lies in the frame
}

TEST(SplitOverlay, DevicesHaveDistinctColours) {
  for (size_t a = 0; a < 8; ++a)
    for (size_t b = a + 1; b < 8; ++b) {
      uint8_t ca[3], cb[3];
      device_colour(a, ca);
      device_colour(b, cb);
      EXPECT_FALSE(ca[0] == cb[0] && ca[1] == cb[1] && ca[2] == cb[2]) << a << " " << b;
    }
}

TEST(SplitOverlay, TheLegendHasText) {
  std::vector<OverlayDevice> devices(1);
  devices[0].name = "cpu:threads=2";
  const Rgb8Image out = split_overlay(grey(200, 10, 0), devices, "frame 0");
  int lit = 0;  // legend pixels drawn in the text's near-white
  for (int y = 10; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) lit += at(out, x, y)[0] > 200 && at(out, x, y)[2] > 200;
  EXPECT_GT(lit, 50);
}

TEST(SplitOverlay, RefusesPixelsThatDoNotMatchTheSize) {
  Rgb8Image bad = grey(4, 4, 0);
  bad.rgb.pop_back();
  EXPECT_THROW(split_overlay(bad, {}, ""), std::invalid_argument);
}

}  // namespace
}  // namespace multiray::study
