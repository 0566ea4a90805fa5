// The report charts' writer (app/svg_chart.h): nice axis maxima, escaped text, lines broken
// at unknown values and clamped to their panel.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "app/svg_chart.h"

namespace multiray::app {
namespace {

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

}  // namespace
}  // namespace multiray::app
