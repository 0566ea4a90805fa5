// Progress a person can plan by (app/progress.h): frame i/N, elapsed, ETA from the mean
// frame time, the rate; a bar on a terminal, a plain line for a pipe.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "app/progress.h"

namespace multiray::app {
namespace {

using ::testing::HasSubstr;

TEST(Progress, EtaIsTheMeanFrameTimeTimesWhatIsLeft) {
  ProgressSnapshot p;
  p.frames_total = 100;
  p.frames_done = 4;
  p.current = 1.0;  // 5 frames' worth in 10 s: 2 s a frame, 95 left
  p.elapsed_s = 10;
  EXPECT_DOUBLE_EQ(eta_seconds(p), 190);
  p.frames_done = 0, p.current = 0.01;  // too little done to tell
  EXPECT_LT(eta_seconds(p), 0);
  p.frames_done = 100, p.current = 0;  // done
  EXPECT_DOUBLE_EQ(eta_seconds(p), 0);
}

TEST(Progress, ClockTimesReadAsPeopleWriteThem) {
  EXPECT_EQ(format_clock(7.4), "0:07");
  EXPECT_EQ(format_clock(725), "12:05");
  EXPECT_EQ(format_clock(3723), "1:02:03");
  EXPECT_EQ(format_clock(-1), "--:--");
}

TEST(Progress, LinesSayFrameElapsedEtaAndRate) {
  ProgressSnapshot p;
  p.frames_total = 100;
  p.frames_done = 49;
  p.current = 0.5;
  p.elapsed_s = 99;    // 49.5 frames: 2 s each, 50.5 left = 101 s
  p.samples = 2.46e6;  // over 2 s of finished frames
  p.samples_elapsed_s = 2;
  const std::string piped = progress_line(p, false);
  EXPECT_EQ(piped, "multiray: frame 50/100 (50% of it), 1:39 elapsed, ETA 1:41, 1.23 Msamples/s");
  const std::string bar = progress_line(p, true, 10);
  EXPECT_THAT(bar, HasSubstr("frame 50/100 [####......]"));  // 49.5% of the run
  EXPECT_THAT(bar, HasSubstr("ETA 1:41"));
  p.frames_done = 0, p.current = 0, p.samples = 0, p.elapsed_s = 0.1;
  EXPECT_THAT(progress_line(p, false), HasSubstr("ETA --:--, rate --"));
}

}  // namespace
}  // namespace multiray::app
