// Byte strings made valid UTF-8 (util/utf8.h): valid text is kept as it is, every other byte
// becomes "\xHH", and the edge cases of RFC 3629 are judged as the RFC says.
#include <gtest/gtest.h>

#include "util/utf8.h"

namespace multiray {
namespace {

TEST(Utf8, ValidTextIsKeptAsItIs) {
  for (const std::string s : {"", "plain/ascii.obj", "caf\xC3\xA9", "\xE2\x82\xAC 5",
                              "\xF0\x9F\x98\x80", "\xEF\xBF\xBF", "\xF4\x8F\xBF\xBF"}) {
    EXPECT_TRUE(is_valid_utf8(s)) << s;
    EXPECT_EQ(escape_invalid_utf8(s), s);
  }
}

TEST(Utf8, EveryInvalidByteIsWrittenAsHex) {
  EXPECT_EQ(escape_invalid_utf8("scene_\xE9\xFF.obj"), "scene_\\xE9\\xFF.obj");
  EXPECT_EQ(escape_invalid_utf8("\x80"), "\\x80");                      // a lone continuation
  EXPECT_EQ(escape_invalid_utf8("a\xC3"), "a\\xC3");                    // cut short at the end
  EXPECT_EQ(escape_invalid_utf8("\xC3\xA9\xC3(x"), "\xC3\xA9\\xC3(x");  // a lead, no tail
  EXPECT_FALSE(is_valid_utf8("\xE9"));
}

TEST(Utf8, OverlongSurrogateAndOutOfRangeFormsAreInvalid) {
  EXPECT_EQ(escape_invalid_utf8("\xC0\xAF"), "\\xC0\\xAF");                    // overlong '/'
  EXPECT_EQ(escape_invalid_utf8("\xE0\x80\xAF"), "\\xE0\\x80\\xAF");           // overlong, 3 bytes
  EXPECT_EQ(escape_invalid_utf8("\xED\xA0\x80"), "\\xED\\xA0\\x80");           // U+D800
  EXPECT_EQ(escape_invalid_utf8("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");  // > U+10FFFF
  EXPECT_EQ(escape_invalid_utf8("\xF5"), "\\xF5");
}

TEST(Utf8, TheResultIsAlwaysValid) {
  std::string all;
  for (int b = 0; b < 256; ++b) all += char(b), all += char(255 - b);
  EXPECT_TRUE(is_valid_utf8(escape_invalid_utf8(all)));
}

}  // namespace
}  // namespace multiray
