// Progress a person can plan by: which frame of how many, the time so far, the time left
// and the rate. Pure functions over a plain snapshot (tested in tests/cli/progress_test.cpp);
// render_command.cpp's ProgressLine samples the run and prints them.
#pragma once

#include <string>

namespace multiray::app {

struct ProgressSnapshot {
  int frames_done = 0;           // frames finished and written
  int frames_total = 1;          // frames asked for
  double current = 0;            // share of the frame in progress handed to devices, [0, 1]
  double elapsed_s = 0;          // since the first frame started
  double samples = 0;            // samples of the finished frames
  double samples_elapsed_s = 0;  // time those frames took (for the rate)
};

// Seconds left, from the mean time per frame so far; negative while too little of the
// run is done to tell (under 2% of one frame).
double eta_seconds(const ProgressSnapshot& p);

// "0:07", "12:05", "1:02:03" (rounded to whole seconds); "--:--" for a negative time.
std::string format_clock(double seconds);

// One line without a line break. On a terminal (`bar`), with a bar of `width` cells:
//   "frame 4/100 [###.......]  37% of it | 0:12 elapsed | ETA 5:10 | 1.23 Msamples/s"
// For a pipe or a log, no bar:
//   "multiray: frame 4/100 (37% of it), 0:12 elapsed, ETA 5:10, 1.23 Msamples/s"
std::string progress_line(const ProgressSnapshot& p, bool bar, int width = 20);

}  // namespace multiray::app
