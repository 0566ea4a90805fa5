// coverage_error() decides exact coverage by a sweep over the items' edges (O(n log n)), not
// by painting every pixel: checked here against a painted frame on random tilings and on
// every way of breaking them (an edge moved, an item dropped or doubled, a view changed).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <random>

#include "balance/plan.h"
#include "partition/coverage.h"

namespace multiray::balance {
namespace coverage_test {

// The answer by painting, as coverage_error once computed it: "" when every pixel is
// covered once, "twice" when some pixel is covered twice, else the first uncovered pixel's
// message (row-major, view by view).
std::string painted(const std::vector<WorkItem>& items, int w, int h, int views) {
  std::vector<uint8_t> hits(size_t(w) * size_t(h) * size_t(views), 0);
  for (const WorkItem& it : items)
    for (int y = it.rect.y0; y < it.rect.y1; ++y)
      for (int x = it.rect.x0; x < it.rect.x1; ++x)
        if (hits[(size_t(it.view) * size_t(h) + size_t(y)) * size_t(w) + size_t(x)]++)
          return "twice";
  for (size_t i = 0; i < hits.size(); ++i)
    if (!hits[i]) {
      const size_t per = size_t(w) * size_t(h), p = i % per;
      return "pixel (" + std::to_string(p % size_t(w)) + "," + std::to_string(p / size_t(w)) +
             ") of view " + std::to_string(i / per) + " is not covered";
    }
  return "";
}

// A random guillotine tiling of one view: rects split at random until small.
void tile(std::mt19937& rng, Rect r, int view, std::vector<WorkItem>& out) {
  const bool wide = r.width() >= r.height();
  const int side = wide ? r.width() : r.height();
  if (side < 2 || rng() % 4 == 0) return out.push_back({r, view});
  const int cut = 1 + int(rng() % uint32_t(side - 1));
  Rect a = r, b = r;
  if (wide)
    a.x1 = b.x0 = r.x0 + cut;
  else
    a.y1 = b.y0 = r.y0 + cut;
  tile(rng, a, view, out);
  tile(rng, b, view, out);
}

TEST(Coverage, TheSweepAgreesWithPaintingOnTilingsAndEveryBreakOfThem) {
  std::mt19937 rng(7);
  int broken = 0, twice = 0;
  for (int round = 0; round < 400; ++round) {
    const int w = 1 + int(rng() % 23), h = 1 + int(rng() % 17), views = 1 + int(rng() % 2);
    std::vector<WorkItem> items;
    for (int v = 0; v < views; ++v) tile(rng, Rect{0, 0, w, h}, v, items);
    ASSERT_EQ(coverage_error(items, w, h, views), "");
    std::shuffle(items.begin(), items.end(), rng);
    // One break of the tiling, or none.
    WorkItem& it = items[rng() % items.size()];
    switch (rng() % 6) {
      case 0:
        it.rect.x1 = std::max(it.rect.x0 + 1, it.rect.x1 - 1);
        break;  // may shrink
      case 1:
        it.rect.y0 = std::max(0, it.rect.y0 - 1);
        break;  // may grow
      case 2:
        items.push_back(it);
        break;  // doubled
      case 3:
        items.erase(items.begin());
        break;  // dropped
      case 4:
        it.view = (it.view + 1) % views;
        break;  // moved
      default:
        break;
    }
    const std::string want = painted(items, w, h, views), got = coverage_error(items, w, h, views);
    if (want == "twice") {
      EXPECT_NE(got.find("is covered twice"), std::string::npos) << got;
      ++twice;
    } else {
      EXPECT_EQ(got, want) << w << "x" << h << "x" << views;
    }
    broken += !want.empty();
  }
  EXPECT_GT(broken, 100);  // the breaks were seen, of both kinds
  EXPECT_GT(twice, 50);
}

TEST(Coverage, NamesAPixelThatTwoItemsCover) {
  const std::vector<WorkItem> items{
      {Rect{0, 0, 4, 2}, 0}, {Rect{2, 1, 3, 3}, 0}, {Rect{0, 2, 4, 3}, 0}};
  const std::string e = coverage_error(items, 4, 3, 1);
  int x = -1, y = -1;
  ASSERT_EQ(std::sscanf(e.c_str(), "pixel (%d,%d) of view 0 is covered twice", &x, &y), 2) << e;
  int covering = 0;
  for (const WorkItem& it : items)
    covering += x >= it.rect.x0 && x < it.rect.x1 && y >= it.rect.y0 && y < it.rect.y1;
  EXPECT_EQ(covering, 2) << e;
  // Touching edges are not an overlap (half-open rects).
  EXPECT_EQ(coverage_error({{Rect{0, 0, 2, 2}, 0}, {Rect{2, 0, 4, 2}, 0}}, 4, 2, 1), "");
}

// An inverted rect ((10,10)-(5,5)) has no pixels, but it is no empty item either: a
// writer that produced it has its corners swapped. Refused, as an item outside the frame is.
TEST(Coverage, AnInvertedRectIsRefused) {
  const std::vector<WorkItem> whole{{Rect{0, 0, 16, 16}, 0}};
  for (const Rect& inverted : {Rect{10, 10, 5, 5}, Rect{10, 0, 5, 4}, Rect{0, 10, 4, 5}}) {
    std::vector<WorkItem> items = whole;
    items.push_back({inverted, 0});
    EXPECT_NE(coverage_error(items, 16, 16, 1).find("is inverted"), std::string::npos)
        << coverage_error(items, 16, 16, 1);
  }
  // Empty rects that are not inverted stay allowed (a balancer's zero share).
  EXPECT_EQ(coverage_error({{Rect{0, 0, 16, 16}, 0}, {Rect{3, 3, 3, 9}, 0}}, 16, 16, 1), "");
}

// check_plan: ratios must sum to 1 (docs/balancers.md); all 0 only for a plan with no work
// (every device dropped, or a frame without pixels). An inverted rect is refused.
TEST(CheckPlan, RefusesAnInvertedRectAndAllZeroRatiosForAPlanWithWork) {
  const FrameShape shape{16, 16, 1, {}};
  Plan plan;
  plan.assigned = {{WorkItem{Rect{0, 0, 16, 8}, 0}}, {WorkItem{Rect{0, 8, 16, 16}, 0}}};
  plan.ratios = {0.5, 0.5};
  ASSERT_EQ(check_plan(plan, shape, 2), "");
  Plan zero = plan;
  zero.ratios = {0, 0};
  EXPECT_NE(check_plan(zero, shape, 2), "");
  Plan inverted = plan;
  inverted.assigned[1].push_back(WorkItem{Rect{10, 10, 5, 5}, 0});
  EXPECT_NE(check_plan(inverted, shape, 2).find("is inverted"), std::string::npos)
      << check_plan(inverted, shape, 2);
  // Nothing to render: all 0 is what a balancer with every device dropped returns.
  Plan none;
  none.assigned = {{}, {}};
  none.ratios = {0, 0};
  EXPECT_EQ(check_plan(none, FrameShape{0, 0, 1, {}}, 2), "");
}

}  // namespace coverage_test
}  // namespace multiray::balance
