// The one strict parser (util/parse.h) and the one --link grammar (util/link.h).
#include "util/parse.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "util/link.h"

namespace multiray {
namespace {

TEST(Parse, ANumberMustFillTheWholeTextAndBeFinite) {
  EXPECT_EQ(parse_number("2"), 2.0);
  EXPECT_EQ(parse_number("-1.5e3"), -1500.0);
  EXPECT_EQ(parse_number("0x10"), 16.0);  // std::stod's hexadecimal, kept
  for (const char* bad : {"", " 2", "2 ", "2x", "x2", "nan", "inf", "-inf", "1e999", ","})
    EXPECT_FALSE(parse_number(bad).has_value()) << '"' << bad << '"';
}

TEST(Parse, SizesTakeBinarySuffixesInEitherCase) {
  EXPECT_EQ(parse_size("100000"), 100000.0);
  EXPECT_EQ(parse_size("1K"), 1024.0);
  EXPECT_EQ(parse_size("1k"), 1024.0);
  EXPECT_EQ(parse_size("512M"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_size("1.5g"), 1.5 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_size("2T"), 2.0 * 1024 * 1024 * 1024 * 1024);
  for (const char* bad : {"", "M", "-1M", "1MB", "1X", "one", " 1M", "1 M", "infM"})
    EXPECT_FALSE(parse_size(bad).has_value()) << '"' << bad << '"';
}

TEST(Parse, BytesAreWrittenWithOneDecimal) {
  EXPECT_EQ(format_bytes(512), "0.5 KiB");
  EXPECT_EQ(format_bytes(3u << 20), "3.0 MiB");
  EXPECT_EQ(format_bytes(uint64_t(5) << 30), "5.0 GiB");
}

TEST(Parse, SplitKeepsEmptyPartsAndJoinUndoesIt) {
  EXPECT_EQ(split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split("a,", ','), (std::vector<std::string>{"a", ""}));
  EXPECT_TRUE(split("", ',').empty());
  EXPECT_EQ(join({"a", "", "b"}, ","), "a,,b");
}

TEST(Link, PresetsAndOneGrammarForCustomLinks) {
  EXPECT_FALSE(parse_link("none").active());
  EXPECT_EQ(parse_link("lan").latency_ms, 0.1);
  EXPECT_EQ(parse_link("wifi").mbit_per_s, 200);
  const LinkSpec l = parse_link("2,100");
  EXPECT_EQ(l.latency_ms, 2);
  EXPECT_EQ(l.mbit_per_s, 100);
  EXPECT_TRUE(l.shared);
  EXPECT_FALSE(parse_link("2,0,separate").shared);
  EXPECT_EQ(parse_link("2,0").mbit_per_s, 0);  // unlimited bandwidth, latency only
  EXPECT_NE(parse_link("wifi").describe().find("emulated"), std::string::npos);
  // The old `simulate` form LAT:MBIT is one of the refused texts: one grammar for both.
  for (const char* bad : {"", "fast", "2", "2:100", "-1,10", "x,10", "1,inf", "1,2,shared",
                          "10001,1", "1,2e6", "1,2,separate,x"})
    EXPECT_THROW(parse_link(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace multiray
