// Frame-time targeting that degrades quality past what shows says so once, with the target
// that would keep it (issue 32: the cranium dropped to step x64 with slab artifacts and no
// word).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "study/adapt_summary.h"

namespace quality_warning_test {

using multiray::study::degraded_quality_warning;
using ::testing::HasSubstr;

TEST(QualityWarning, SaysWhatTargetKeepsTheQuality) {
  // Step x64: 1/64 of the work in 50 ms, so about 50 * 64 / 4 = 800 ms keeps step x4.
  const std::string w = degraded_quality_warning(64.0, 1.0, 50.0, 50.0);
  EXPECT_THAT(w, HasSubstr("--target-ms 50 "));
  EXPECT_THAT(w, HasSubstr("64x less"));
  EXPECT_THAT(w, HasSubstr("About --target-ms 800 keeps"));
  // Image space: half the pixels per side is a quarter of the work; below it warns.
  EXPECT_THAT(degraded_quality_warning(1.0, 0.25, 30.0, 30.0),
              HasSubstr("About --target-ms 120 "));
  // A frame over its target: the estimate starts from the time it took.
  EXPECT_THAT(degraded_quality_warning(8.0, 1.0, 60.0, 50.0), HasSubstr("About --target-ms 120 "));
}

TEST(QualityWarning, QuietWhileTheQualityHolds) {
  EXPECT_EQ(degraded_quality_warning(1.0, 1.0, 50.0, 50.0), "");
  EXPECT_EQ(degraded_quality_warning(4.0, 1.0, 50.0, 50.0), "");  // exactly the bound
  EXPECT_EQ(degraded_quality_warning(2.0, 0.75, 50.0, 50.0), "");
  EXPECT_EQ(degraded_quality_warning(64.0, 1.0, 50.0, 0.0), "");  // no target
}

}  // namespace quality_warning_test
