#include <time.h>

#include <thread>

#include "device/device.h"

namespace multiray {

SlowdownEmulator::SlowdownEmulator(double speed)
    : speed_(speed), start_(std::chrono::steady_clock::now()) {}

void SlowdownEmulator::after_unit(double busy_ms) {
  if (!(busy_ms > 0)) return;
  busy_total_ms_ += busy_ms;
  if (!(speed_ > 0) || speed_ >= 1.0) return;
  const auto deadline =
      start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double, std::milli>(busy_total_ms_ / speed_));
  std::this_thread::sleep_until(deadline);
}

namespace {
int64_t clock_ns(clockid_t id) {
  timespec t{};
  if (clock_gettime(id, &t) != 0) return 0;
  return int64_t(t.tv_sec) * 1000000000 + int64_t(t.tv_nsec);
}
}  // namespace

ThreadTimes::ThreadTimes(std::atomic<int64_t>* stolen_ns) : stolen_ns_(stolen_ns) {
  if (!stolen_ns_) return;
  wall_ns_ = clock_ns(CLOCK_MONOTONIC);
  cpu_ns_ = clock_ns(CLOCK_THREAD_CPUTIME_ID);
}

ThreadTimes::~ThreadTimes() {
  if (!stolen_ns_) return;
  const int64_t cpu = clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu_ns_;
  const int64_t wall = clock_ns(CLOCK_MONOTONIC) - wall_ns_;
  if (wall > cpu) *stolen_ns_ += wall - cpu;
}

double SlowdownEmulator::thread_cpu_ms() {
  return double(clock_ns(CLOCK_THREAD_CPUTIME_ID)) * 1e-6;
}

}  // namespace multiray
