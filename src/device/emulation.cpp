#include <chrono>
#include <thread>

#include "device/device.h"

namespace multiray {

double emulate_slowdown(double busy_ms, double speed) {
  if (!(speed > 0) || speed >= 1.0 || !(busy_ms > 0)) return 0.0;
  const double idle_ms = busy_ms * (1.0 / speed - 1.0);
  // sleep_for may overshoot by a scheduler tick; the caller measures the real time spent.
  std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(idle_ms));
  return idle_ms;
}

}  // namespace multiray
