// Harada's hierarchy (GPU Pro 7, ch. 4, Fig. 4.5): machines get horizontal bands, each
// machine cuts its band vertically across its devices. Checked on the planned items of both
// levels, as the MPI master and a rank's worker build them.
#include <gtest/gtest.h>

#include "balance/hierarchy.h"
#include "balance/region.h"

namespace multiray::balance {
namespace hierarchy_test {

// The direction in which `p` cut `part`: rows when every item more than a pixel high spans
// the part's width, columns when every item more than a pixel wide spans its height (the
// cuts are at pixel precision, so a one-pixel remainder is either).
CutAxis cut_direction(const Plan& p, const Rect& part) {
  bool rows = true, columns = true;
  int pieces = 0;
  for (const WorkItem& it : p.all_items()) {
    const Rect& r = it.rect;
    EXPECT_TRUE(r.x0 >= part.x0 && r.x1 <= part.x1 && r.y0 >= part.y0 && r.y1 <= part.y1);
    if (r.height() > 1 && (r.x0 != part.x0 || r.x1 != part.x1)) rows = false;
    if (r.width() > 1 && (r.y0 != part.y0 || r.y1 != part.y1)) columns = false;
    ++pieces;
  }
  if (pieces < 2 || rows == columns) return CutAxis::none;
  return rows ? CutAxis::rows : CutAxis::columns;
}

// The rank's split of the part the master gave it, as distributed/rank_worker.cpp makes it.
Plan rank_plan(const std::string& spec, const FrameShape& shape, const Rect& part,
               bool same_direction = false) {
  std::unique_ptr<Balancer> inner = make_balancer(spec, 3);
  const CutAxis native = inner->cut_axis();
  const bool transposed =
      lower_level_transposed(band_axis(part, shape.width, shape.height), native, same_direction);
  RegionBalancer rank(std::move(inner), Region{part, -1, transposed});
  return rank.plan(shape, 0);
}

// The biggest item of device `i` of the master's plan: that rank's band.
Rect band_of(const Plan& p, int i) {
  Rect best;
  for (const WorkItem& it : p.assigned[size_t(i)])
    if (it.rect.area() > best.area()) best = it.rect;
  return best;
}

TEST(Hierarchy, MachinesGetRowBandsAndSplitThemIntoColumns) {
  const FrameShape shape{240, 160, 1, {}};
  const Rect frame{0, 0, 240, 160};
  std::unique_ptr<Balancer> master = make_balancer(top_level_spec("semi-static"), 3);
  const Plan top = master->plan(shape, 0);
  EXPECT_EQ(master->cut_axis(), CutAxis::rows);
  EXPECT_EQ(cut_direction(top, frame), CutAxis::rows);
  for (const std::vector<WorkItem>& rank : top.assigned)  // one whole-row band a rank
    ASSERT_EQ(rank.size(), 1u);
  for (int r = 0; r < 3; ++r) {
    const Rect band = band_of(top, r);
    ASSERT_EQ(band_axis(band, shape.width, shape.height), CutAxis::rows);
    EXPECT_EQ(cut_direction(rank_plan("semi-static", shape, band), band), CutAxis::columns);
    // A balancer that cuts rows of its own is turned to cut across the band too.
    EXPECT_EQ(cut_direction(rank_plan("uniform", shape, band), band), CutAxis::columns);
    EXPECT_EQ(cut_direction(rank_plan("hybrid:bands=1", shape, band), band), CutAxis::columns);
    // --rank-same-direction: along the band.
    EXPECT_EQ(cut_direction(rank_plan("semi-static", shape, band, true), band), CutAxis::rows);
  }
}

TEST(Hierarchy, ColumnBandsFromTheMasterAreCutIntoRows) {
  const FrameShape shape{240, 160, 1, {}};
  std::unique_ptr<Balancer> master = make_balancer("uniform:layout=columns", 3);
  const Plan top = master->plan(shape, 0);
  for (int r = 0; r < 3; ++r) {
    const Rect band = band_of(top, r);
    ASSERT_EQ(band_axis(band, shape.width, shape.height), CutAxis::columns);
    EXPECT_EQ(cut_direction(rank_plan("semi-static", shape, band), band), CutAxis::rows);
    EXPECT_EQ(cut_direction(rank_plan("uniform", shape, band), band), CutAxis::rows);
  }
}

TEST(Hierarchy, OnlyAnUnsplitSemiStaticChangesAtTheTop) {
  EXPECT_EQ(top_level_spec("semi-static"), "semi-static:split=rows:cut=line");
  EXPECT_EQ(top_level_spec("semi-static:alpha=0.2"), "semi-static:alpha=0.2:split=rows:cut=line");
  EXPECT_EQ(top_level_spec("semi-static:cut=pixel"), "semi-static:cut=pixel:split=rows");
  EXPECT_EQ(top_level_spec("semi-static:split=columns"), "semi-static:split=columns");
  EXPECT_EQ(top_level_spec("hybrid"), "hybrid");
  EXPECT_EQ(top_level_spec("uniform:layout=columns"), "uniform:layout=columns");
}

TEST(Hierarchy, PartsWithoutADirectionLeaveTheLowerLevelAsItIs) {
  EXPECT_EQ(band_axis(Rect{0, 0, 240, 160}, 240, 160), CutAxis::none);  // the whole frame
  EXPECT_EQ(band_axis(Rect{16, 16, 32, 32}, 240, 160), CutAxis::none);  // a tile
  EXPECT_EQ(band_axis(Rect{0, 0, 300, 10}, 240, 160), CutAxis::none);   // outside
  EXPECT_EQ(band_axis(Rect{}, 240, 160), CutAxis::none);
  EXPECT_FALSE(lower_level_transposed(CutAxis::none, CutAxis::columns, false));
  EXPECT_FALSE(lower_level_transposed(CutAxis::rows, CutAxis::none, false));
  // The whole frame handed to one rank: semi-static cuts columns, as on one machine.
  const FrameShape shape{240, 160, 1, {}};
  const Rect frame{0, 0, 240, 160};
  EXPECT_EQ(cut_direction(rank_plan("semi-static", shape, frame), frame), CutAxis::columns);
}

}  // namespace hierarchy_test
}  // namespace multiray::balance
