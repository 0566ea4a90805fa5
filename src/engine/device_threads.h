// One long-lived thread per device. Devices pin their thread to cores and move it into a
// CPU-quota cgroup the first time it renders; with a fresh thread every frame that set-up
// (a cgroup v1 migration can take tens of ms) would be paid, and mis-timed, every frame.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace multiray {

class DeviceThreads {
 public:
  explicit DeviceThreads(size_t count);
  ~DeviceThreads();
  DeviceThreads(const DeviceThreads&) = delete;
  DeviceThreads& operator=(const DeviceThreads&) = delete;

  // Runs jobs[i] on thread i (empty jobs are skipped) and returns when all have finished.
  // Jobs must not throw. Not reentrant: one run() at a time.
  void run(const std::vector<std::function<void()>>& jobs);

 private:
  void loop(size_t index);

  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::vector<std::function<void()>>* jobs_ = nullptr;
  uint64_t generation_ = 0;
  size_t pending_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace multiray
