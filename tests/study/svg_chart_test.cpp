// The report charts' writer (study/svg_chart.h): nice axis maxima, escaped text, lines broken
// at unknown values and clamped to their panel, round frame ticks, the shaded warm-up,
// stacked layers; and the bench timelines' shared scale and ideal split (study/report_plots.h).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "study/report_plots.h"
#include "study/svg_chart.h"

namespace multiray::study {
namespace svg_chart_test {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(SvgChart, NiceCeilings) {
  EXPECT_DOUBLE_EQ(nice_ceiling(1), 1);
  EXPECT_DOUBLE_EQ(nice_ceiling(1.01), 2);
  EXPECT_DOUBLE_EQ(nice_ceiling(3), 5);
  EXPECT_DOUBLE_EQ(nice_ceiling(7), 10);
  EXPECT_DOUBLE_EQ(nice_ceiling(180), 200);
  EXPECT_DOUBLE_EQ(nice_ceiling(0.03), 0.05);
  EXPECT_DOUBLE_EQ(nice_ceiling(0), 1);
  EXPECT_DOUBLE_EQ(nice_ceiling(NAN), 1);
}

TEST(SvgChart, EscapesTextAndBreaksLinesAtUnknownValues) {
  SvgChart chart("a <b> & 'c'", 4);
  const int p = chart.add_panel("ms", 80, 100);
  chart.line(p, {1, 2, NAN, 4}, "#000");
  chart.legend(p, {{"x<y", "#f00"}});
  const std::string svg = chart.svg();
  EXPECT_NE(svg.find("a &lt;b&gt; &amp; &apos;c&apos;"), std::string::npos);
  EXPECT_NE(svg.find("x&lt;y"), std::string::npos);
  EXPECT_EQ(svg.find("<b>"), std::string::npos);
  EXPECT_EQ(count(svg, "<polyline"), 2u);           // frames 0-1, then frame 3 alone
  EXPECT_NE(svg.find(">100<"), std::string::npos);  // the axis maximum: nice_ceiling(80)
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

TEST(SvgChart, ValuesOutsideThePanelAreDrawnAtItsEdge) {
  SvgChart chart("t", 2);
  const int p = chart.add_panel("%", 100, 100);
  chart.line(p, {-50, 500}, "#000");
  // Panel 0 starts at y = 40 and is 100 px tall: -50 clamps to 140, 500 to 40.
  EXPECT_NE(chart.svg().find(",140.0 "), std::string::npos);
  EXPECT_NE(chart.svg().find(",40.0 "), std::string::npos);
}

}  // namespace svg_chart_test
}  // namespace multiray::study

namespace multiray::study {
namespace svg_chart_test {

// Frame numbers under the chart fall on round steps; the warm-up is shaded and labelled;
// stacked layers are one polygon each.
TEST(SvgChart, RoundFrameTicksShadedWarmupAndStackedLayers) {
  SvgChart chart("t", 100);
  const int p = chart.add_panel("share", 1.0, 100);
  chart.stacked(p, {std::vector<double>(100, 0.3), std::vector<double>(100, 0.7)},
                {"#111111", "#222222"});
  chart.shade(0, 9, "warm-up");
  const std::string svg = chart.svg();
  for (const char* tick : {">20</text>", ">40</text>", ">60</text>", ">80</text>"})
    EXPECT_EQ(count(svg, tick), 1u) << tick;
  EXPECT_EQ(count(svg, ">99</text>"), 0u);  // 99 / 8 rounds up to steps of 20
  EXPECT_EQ(count(svg, "<polygon"), 2u);
  EXPECT_EQ(count(svg, ">warm-up</text>"), 1u);
  EXPECT_EQ(count(svg, "fill-opacity='0.07'"), 1u);  // one panel, one band
}

// The ideal split between timed frames follows the devices' speeds linearly; the time
// scale shared by a run's timelines leaves the warm-up out.
TEST(Report, TimelineScaleInterpolatesIdealSharesAndSkipsTheWarmup) {
  BenchResult result;
  result.ideal = {IdealSample{0, {10, 20}, 0}, IdealSample{10, {10, 10}, 0}};
  result.lanes.resize(1);
  for (int f = 0; f < 12; ++f) {
    FrameRecord r;
    r.frame = f;
    r.devices.resize(2);
    r.devices[0].time_ms = f == 0 ? 500 : 20;  // the first frame's set-up
    result.lanes[0].records.push_back(r);
  }
  const TimelineScale s = timeline_scale(result, 2, 12);
  EXPECT_DOUBLE_EQ(s.time_max_ms, 20);
  ASSERT_EQ(s.ideal_share.size(), 12u);
  EXPECT_NEAR(s.ideal_share[0][0], 2.0 / 3.0, 1e-12);    // speeds 0.1 : 0.05
  EXPECT_NEAR(s.ideal_share[5][0], 0.1 / 0.175, 1e-12);  // 0.1 : 0.075
  EXPECT_NEAR(s.ideal_share[11][1], 0.5, 1e-12);         // clamped after the last
}

}  // namespace svg_chart_test
}  // namespace multiray::study
