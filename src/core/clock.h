// Monotonic time in milliseconds as double. All timings in multiray are taken with this
// clock, inside the device that does the work.
#pragma once

#include <chrono>

namespace multiray {

using SteadyClock = std::chrono::steady_clock;

inline double ms_between(SteadyClock::time_point a, SteadyClock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

class Stopwatch {
 public:
  Stopwatch() : start_(SteadyClock::now()) {}
  double elapsed_ms() const { return ms_between(start_, SteadyClock::now()); }
  void restart() { start_ = SteadyClock::now(); }

 private:
  SteadyClock::time_point start_;
};

}  // namespace multiray
