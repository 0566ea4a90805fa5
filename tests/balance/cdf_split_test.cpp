// The CDF splitter (Harada, GPU Pro 7 ch. 4; Harada & Fujita 2014): each device gets its
// target share of the weight to within one row's worth, zeros give empty ranges, and the
// bands cover the image exactly once.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "partition/apportion.h"
#include "partition/cdf_split.h"
#include "partition/coverage.h"
#include "partition_cases.h"

namespace multiray::balance {
namespace cdf_split_test {

double sum(const std::vector<double>& w, int64_t a, int64_t b) {
  return std::accumulate(w.begin() + a, w.begin() + b, 0.0);
}

TEST(CdfSplit, EachBandGetsItsShareWithinOneRow) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int rows : {1, 2, 13, 359, 1000})
    for (int devices : kDeviceCounts)
      for (const auto& shares : ratio_cases(rng, devices)) {
        std::vector<double> w(static_cast<size_t>(rows));
        for (double& x : w)
          x = u(rng) < 0.1 ? 0.0 : std::pow(u(rng), 3) * 100;  // spiky, with gaps
        const double total = sum(w, 0, rows);
        const double max_row = *std::max_element(w.begin(), w.end());
        const std::vector<Rect> bands = cdf_split_rows(17, w, shares);
        const std::vector<double> target = normalized_ratios(shares);
        std::vector<WorkItem> items;
        for (int i = 0; i < devices; ++i) {
          const Rect& r = bands[size_t(i)];
          items.push_back(WorkItem{r, 0});
          const double got = total > 0 ? sum(w, r.y0, r.y1) : 0;
          if (total > 0) {
            EXPECT_LE(std::abs(got - target[size_t(i)] * total), max_row + 1e-9 * total)
                << rows << " rows, device " << i << " of " << devices;
          }
          if (shares[size_t(i)] == 0 &&
              std::any_of(shares.begin(), shares.end(), [](double s) { return s > 0; })) {
            EXPECT_TRUE(r.empty());
          }
        }
        ASSERT_EQ(coverage_error(items, 17, rows, 1), "");
      }
}

TEST(CdfSplit, FollowsWeightNotArea) {
  // Rows 0–9 weigh 1, rows 10–19 weigh 3: equal halves of the weight cut at row 13.33 → 13.
  std::vector<double> w(20, 1.0);
  std::fill(w.begin() + 10, w.end(), 3.0);
  const std::vector<Rect> bands = cdf_split_rows(8, w, {1, 1});
  EXPECT_EQ(bands[0], (Rect{0, 0, 8, 13}));
  EXPECT_EQ(bands[1], (Rect{0, 13, 8, 20}));
  const std::vector<Rect> cols = cdf_split_columns(4, w, {1, 1});
  EXPECT_EQ(cols[0], (Rect{0, 0, 13, 4}));
}

TEST(CdfSplit, InterpolatesInsideCellsAtUnitPrecision) {
  // Two rows of 100 px, weights 1 and 3: the half-weight cut lies 1/3 into row 1.
  const std::vector<int64_t> cuts = cdf_cuts({1.0, 3.0}, 100, {1, 1});
  EXPECT_EQ(cuts, (std::vector<int64_t>{0, 133, 200}));
}

TEST(CdfSplit, ZeroOrGarbageWeightFallsBackToArea) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(cdf_cuts({0, 0, 0, 0}, 1, {1, 1}), (std::vector<int64_t>{0, 2, 4}));
  EXPECT_EQ(cdf_cuts({nan, -1, nan, -1}, 1, {1, 3}), (std::vector<int64_t>{0, 1, 4}));
  EXPECT_EQ(cdf_cuts({}, 1, {1, 1}), (std::vector<int64_t>{0, 0, 0}));
}

TEST(CdfSplit, PixelSplitIsWithinOnePixelOfTarget) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  const int w = 61, h = 37;
  std::vector<double> px(size_t(w * h));
  for (double& x : px) x = std::floor(u(rng));  // 0–3 samples per pixel, like adaptive AO
  const std::vector<double> shares = {0.5, 0.2, 0.0, 0.3};
  const auto lists = cdf_split_pixels(w, h, 0, px, shares);
  const double total = sum(px, 0, int64_t(px.size()));
  std::vector<WorkItem> all;
  for (size_t i = 0; i < lists.size(); ++i) {
    double got = 0;
    for (const WorkItem& item : lists[i]) {
      all.push_back(item);
      for (int y = item.rect.y0; y < item.rect.y1; ++y)
        for (int x = item.rect.x0; x < item.rect.x1; ++x) got += px[size_t(y * w + x)];
      EXPECT_LE(lists[i].size(), 3u);
    }
    EXPECT_LE(std::abs(got - shares[i] * total), 2 * 3.0 + 1e-9) << "device " << i;
  }
  EXPECT_TRUE(lists[2].empty());
  EXPECT_EQ(coverage_error(all, w, h, 1), "");
}

}  // namespace cdf_split_test
}  // namespace multiray::balance
