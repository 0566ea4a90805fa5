// Bands, tiles, apportioning and scanline ranges: every split covers every pixel exactly
// once, for any ratios, device counts up to 64 and awkward resolutions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "balance/layout.h"
#include "partition/apportion.h"
#include "partition/bands.h"
#include "partition/coverage.h"
#include "partition/scanline.h"
#include "partition/tiles.h"
#include "partition_cases.h"

namespace multiray::balance {
namespace partition_test {

TEST(Apportion, SumsExactlyAndStaysWithinOneOfQuota) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::vector<double> ratios = random_ratios(rng, 1 + int(rng() % 64));
    const int64_t total = int64_t(rng() % 100000);
    const std::vector<int64_t> c = apportion(ratios, total);
    ASSERT_EQ(std::accumulate(c.begin(), c.end(), int64_t(0)), total);
    const std::vector<double> w = normalized_ratios(ratios);
    const bool any = std::any_of(ratios.begin(), ratios.end(), [](double r) { return r > 0; });
    for (size_t i = 0; i < c.size(); ++i) {
      EXPECT_LT(std::abs(double(c[i]) - w[i] * double(total)), 1.0 + 1e-9);
      if (any && ratios[i] == 0) {
        EXPECT_EQ(c[i], 0);
      }
    }
  }
}

TEST(Apportion, LargestRemainderAndTies) {
  EXPECT_EQ(apportion({1, 1, 1}, 10), (std::vector<int64_t>{4, 3, 3}));  // tie: lower index
  EXPECT_EQ(apportion({3, 1}, 7), (std::vector<int64_t>{5, 2}));         // 5.25, 1.75
  EXPECT_EQ(apportion({0, 1, 0}, 5), (std::vector<int64_t>{0, 5, 0}));
  EXPECT_EQ(apportion({1, 0}, 0), (std::vector<int64_t>{0, 0}));
}

TEST(Apportion, GarbageRatiosNeverLosePixels) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(apportion({nan, -1, inf}, 9), (std::vector<int64_t>{3, 3, 3}));  // all unusable
  EXPECT_EQ(apportion({nan, 2, -5}, 9), (std::vector<int64_t>{0, 9, 0}));
  EXPECT_EQ(apportion({1e-300, 1e300}, 4), (std::vector<int64_t>{0, 4}));
  EXPECT_TRUE(apportion({}, 5).empty());
}

TEST(Bands, CoverEveryPixelOnceForAnyRatios) {
  std::mt19937_64 rng(11);
  for (const Size& size : kSizes)
    for (int devices : kDeviceCounts)
      for (const auto& ratios : ratio_cases(rng, devices))
        for (Axis axis : {Axis::Rows, Axis::Columns}) {
          const std::vector<Rect> bands = split_bands(size.w, size.h, ratios, axis);
          ASSERT_EQ(bands.size(), size_t(devices));
          std::vector<WorkItem> items;
          for (const Rect& r : bands) items.push_back(WorkItem{r, 0});
          ASSERT_EQ(coverage_error(items, size.w, size.h, 1), "")
              << size.w << "x" << size.h << " devices " << devices;
          const bool any =
              std::any_of(ratios.begin(), ratios.end(), [](double r) { return r > 0; });
          for (int i = 0; i < devices; ++i)
            if (any && ratios[size_t(i)] == 0) {
              EXPECT_TRUE(bands[size_t(i)].empty());
            }
        }
}

TEST(Bands, FollowRatiosAlongTheAxis) {
  const std::vector<Rect> rows = split_bands(10, 100, {3, 1}, Axis::Rows);
  EXPECT_EQ(rows[0], (Rect{0, 0, 10, 75}));
  EXPECT_EQ(rows[1], (Rect{0, 75, 10, 100}));
  const std::vector<Rect> cols = split_bands(8, 2, {1, 0, 1}, Axis::Columns);
  EXPECT_EQ(cols[0], (Rect{0, 0, 4, 2}));
  EXPECT_TRUE(cols[1].empty());
  EXPECT_EQ(cols[2], (Rect{4, 0, 8, 2}));
}

TEST(Tiles, CoverAndClipAtEdges) {
  for (const Size& size : kSizes)
    for (int tile : {1, 7, 32, 64, 1000}) {
      std::vector<WorkItem> items;
      for (const Rect& r : make_tiles(size.w, size.h, tile)) {
        EXPECT_LE(r.width(), tile);
        EXPECT_LE(r.height(), tile);
        items.push_back(WorkItem{r, 0});
      }
      ASSERT_EQ(coverage_error(items, size.w, size.h, 1), "") << size.w << "x" << size.h;
    }
  EXPECT_EQ(make_tiles(100, 10, 64).size(), 2u);
  EXPECT_EQ(make_tiles(100, 10, 64)[1], (Rect{64, 0, 100, 10}));
  EXPECT_THROW(make_tiles(10, 10, 0), std::invalid_argument);
  EXPECT_TRUE(make_tiles(0, 10, 8).empty());
}

TEST(Scanline, RangeBecomesAtMostThreeRects) {
  std::vector<WorkItem> out;
  append_scanline_rects(10, 7, 35, 2, out);  // 3 px of row 0, rows 1–2, 5 px of row 3
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].rect, (Rect{7, 0, 10, 1}));
  EXPECT_EQ(out[1].rect, (Rect{0, 1, 10, 3}));
  EXPECT_EQ(out[2].rect, (Rect{0, 3, 5, 4}));
  EXPECT_EQ(out[2].view, 2);
  out.clear();
  append_scanline_rects(10, 3, 6, 0, out);  // inside one row
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].rect, (Rect{3, 0, 6, 1}));
}

TEST(Scanline, RandomCutsOfFlatViewsCoverOnce) {
  std::mt19937_64 rng(3);
  for (const Size& size : kSizes)
    for (int views : {1, 2, 9}) {
      const int64_t total = int64_t(size.w) * size.h * views;
      std::vector<int64_t> cuts = {0, total};
      for (int k = 0; k < 10; ++k) cuts.push_back(int64_t(rng() % uint64_t(total + 1)));
      std::sort(cuts.begin(), cuts.end());
      std::vector<WorkItem> items;
      for (size_t k = 0; k + 1 < cuts.size(); ++k)
        append_flat_range(size.w, size.h, cuts[k], cuts[k + 1], items);
      ASSERT_EQ(coverage_error(items, size.w, size.h, views), "");
    }
}

// Column order: a partial column, whole columns, a partial column; random cuts over
// views side by side cover every pixel once.
TEST(Scanline, ColumnRangesAreVerticalBandsThatCoverOnce) {
  std::vector<WorkItem> out;
  append_flat_column_range(4, 10, 7, 35, out);  // 3 px of column 0, columns 1-2, 5 of 3
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].rect, (Rect{0, 7, 1, 10}));
  EXPECT_EQ(out[1].rect, (Rect{1, 0, 3, 10}));
  EXPECT_EQ(out[2].rect, (Rect{3, 0, 4, 5}));
  std::mt19937_64 rng(5);
  for (const Size& size : kSizes)
    for (int views : {1, 3}) {
      const int64_t total = int64_t(size.w) * size.h * views;
      std::vector<int64_t> cuts = {0, total};
      for (int k = 0; k < 10; ++k) cuts.push_back(int64_t(rng() % uint64_t(total + 1)));
      std::sort(cuts.begin(), cuts.end());
      std::vector<WorkItem> items;
      for (size_t k = 0; k + 1 < cuts.size(); ++k)
        append_flat_column_range(size.w, size.h, cuts[k], cuts[k + 1], items);
      ASSERT_EQ(coverage_error(items, size.w, size.h, views), "");
    }
}

TEST(Coverage, ReportsOverlapGapsAndOutOfBounds) {
  EXPECT_NE(coverage_error({{Rect{0, 0, 2, 2}, 0}, {Rect{1, 1, 2, 2}, 0}}, 2, 2, 1), "");
  EXPECT_NE(coverage_error({{Rect{0, 0, 2, 1}, 0}}, 2, 2, 1), "");
  EXPECT_NE(coverage_error({{Rect{0, 0, 3, 2}, 0}}, 2, 2, 1), "");
  EXPECT_NE(coverage_error({{Rect{0, 0, 2, 2}, 1}}, 2, 2, 1), "");
  EXPECT_EQ(coverage_error({{Rect{0, 0, 2, 2}, 0}, {Rect{5, 5, 5, 9}, 0}}, 2, 2, 1), "");
}

}  // namespace partition_test
}  // namespace multiray::balance

// Whole views per device (multiray's own view mapping; Leria et al. split every view over
// every device): each view goes to exactly one device, in proportion to the ratios.
TEST(ViewsLayout, AssignsWholeViewsByRatio) {
  using namespace multiray::balance;
  FrameShape shape{16, 9, 9, {}};
  const Plan plan = plan_from_ratios(shape, {0.75, 0.25}, Layout::Views);
  EXPECT_EQ(check_plan(plan, shape, 2), "");
  ASSERT_EQ(plan.assigned.size(), 2u);
  EXPECT_EQ(plan.assigned[0].size(), 7u);  // round(0.75 * 9) by largest remainder
  EXPECT_EQ(plan.assigned[1].size(), 2u);
  for (const auto& list : plan.assigned)
    for (const WorkItem& it : list) EXPECT_EQ(it.rect.area(), 16 * 9);
}
