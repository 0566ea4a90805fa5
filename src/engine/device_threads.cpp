#include "engine/device_threads.h"

namespace multiray {

DeviceThreads::DeviceThreads(size_t count) {
  threads_.reserve(count);
  for (size_t i = 0; i < count; ++i) threads_.emplace_back([this, i] { loop(i); });
}

DeviceThreads::~DeviceThreads() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& t : threads_) t.join();
}

void DeviceThreads::run(const std::vector<std::function<void()>>& jobs) {
  std::unique_lock<std::mutex> lock(mutex_);
  jobs_ = &jobs;
  pending_ = threads_.size();
  ++generation_;
  start_.notify_all();
  done_.wait(lock, [&] { return pending_ == 0; });
  jobs_ = nullptr;
}

void DeviceThreads::loop(size_t index) {
  uint64_t seen = 0;
  for (;;) {
    const std::function<void()>* job = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (index < jobs_->size() && (*jobs_)[index]) job = &(*jobs_)[index];
    }
    if (job) (*job)();
    std::lock_guard<std::mutex> lock(mutex_);
    if (--pending_ == 0) done_.notify_one();
  }
}

}  // namespace multiray
