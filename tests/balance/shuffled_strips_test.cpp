// Shuffled strips (van Antwerpen, Seibert & Keller 2019): strip size, the bit-reversal
// permutation, shares of round(w·2^b) strips, and exact coverage of every view.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "partition/apportion.h"
#include "partition/coverage.h"
#include "partition/shuffled_strips.h"
#include "partition_cases.h"

namespace multiray::balance {
namespace shuffled_strips_test {

TEST(ShuffledStrips, StripsHold128To256Pixels) {
  for (int64_t pixels : {256, 1000, 640 * 360, 641 * 359, 1920 * 1080, 123457}) {
    const int b = strip_bits_for(pixels);
    for (int64_t k = 0; k < (int64_t(1) << b); ++k) {
      int64_t begin = 0, end = 0;
      strip_range(pixels, b, k, begin, end);
      EXPECT_GE(end - begin, 128) << pixels;
      EXPECT_LE(end - begin, 256) << pixels;
    }
  }
  EXPECT_EQ(strip_bits_for(640 * 360), 10);  // 225 px per strip
  EXPECT_EQ(strip_bits_for(1), 0);           // tiny: one strip
  EXPECT_EQ(strip_bits_for(255), 0);
}

// Leria et al.'s rule (the most strips: 2^19 at 1280x720) and the dlb default's floor.
TEST(ShuffledStrips, LeastPixelsPerStripSetsTheCount) {
  EXPECT_EQ(strip_bits_for(1280 * 720, 1), 19);   // ~1.76 px per strip, the paper's Fig. 3
  EXPECT_EQ(strip_bits_for(1280 * 720, 32), 14);  // 56.25 px
  EXPECT_EQ(strip_bits_for(320 * 180, 32), 10);   // 56.25 px
  for (int64_t least : {1, 7, 32, 500})
    for (int64_t pixels : {1000, 57600, 921600}) {
      const int b = strip_bits_for(pixels, least);
      if (b == 0) continue;
      EXPECT_GE(pixels >> b, least);
      EXPECT_LT(pixels >> (b + 1), least) << "not the largest count";
    }
}

TEST(ShuffledStrips, BitReversalIsAPermutation) {
  EXPECT_EQ(bit_reverse(1, 3), 4u);
  EXPECT_EQ(bit_reverse(6, 3), 3u);
  EXPECT_EQ(bit_reverse(5, 0), 0u);
  for (int bits : {0, 1, 4, 10}) {
    std::set<uint32_t> seen;
    for (uint32_t v = 0; v < (1u << bits); ++v) seen.insert(bit_reverse(v, bits));
    EXPECT_EQ(seen.size(), size_t(1) << bits);
    EXPECT_EQ(*seen.rbegin(), (1u << bits) - 1);
  }
}

TEST(ShuffledStrips, CoverEveryViewOnceForAnyRatios) {
  std::mt19937_64 rng(5);
  for (const Size& size : kSizes)
    for (int devices : kDeviceCounts)
      for (int views : {1, 3})
        for (const auto& ratios : ratio_cases(rng, devices)) {
          const auto lists = shuffled_strips(size.w, size.h, views, ratios);
          ASSERT_EQ(lists.size(), size_t(devices));
          std::vector<WorkItem> all;
          for (const auto& l : lists) all.insert(all.end(), l.begin(), l.end());
          ASSERT_EQ(coverage_error(all, size.w, size.h, views), "")
              << size.w << "x" << size.h << " devices " << devices << " views " << views;
        }
}

TEST(ShuffledStrips, DeviceGetsRoundedShareOfStripsInEveryView) {
  const int w = 640, h = 360, views = 4;
  const std::vector<double> ratios = {0.62, 0.0, 0.38};
  const auto lists = shuffled_strips(w, h, views, ratios);
  const std::vector<int64_t> strips = apportion(ratios, 1024);
  EXPECT_EQ(strips, (std::vector<int64_t>{635, 0, 389}));
  EXPECT_TRUE(lists[1].empty());
  for (size_t i = 0; i < lists.size(); ++i)
    for (int v = 0; v < views; ++v) {
      int64_t pixels = 0;
      for (const WorkItem& item : lists[i])
        if (item.view == v) pixels += item.rect.area();
      // Strips are 225 px here; the device's pixels are its strip count times that.
      EXPECT_EQ(pixels, strips[i] * 225) << "device " << i << " view " << v;
    }
}

TEST(ShuffledStrips, ConsecutivePositionsSpreadOverTheImage) {
  // Half the strips (device 0 of an even pair) must cover both halves of the image evenly:
  // bit reversal puts every other strip in it.
  const auto lists = shuffled_strips(640, 360, 1, {1, 1});
  int64_t top = 0, bottom = 0;
  for (const WorkItem& item : lists[0]) (item.rect.y0 < 180 ? top : bottom) += item.rect.area();
  EXPECT_NEAR(double(top) / double(top + bottom), 0.5, 0.01);
}

TEST(ShuffledStrips, ExplicitBitsAreClampedForTinyImages) {
  const auto lists = shuffled_strips(3, 2, 1, {1, 1, 1}, 20);  // 6 px: at most 4 strips
  std::vector<WorkItem> all;
  for (const auto& l : lists) all.insert(all.end(), l.begin(), l.end());
  EXPECT_EQ(coverage_error(all, 3, 2, 1), "");
}

}  // namespace shuffled_strips_test
}  // namespace multiray::balance
