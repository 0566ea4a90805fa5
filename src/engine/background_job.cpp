#include "engine/background_job.h"

#include <stdexcept>

namespace multiray {

BackgroundJob::~BackgroundJob() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return !running_; });
    quit_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void BackgroundJob::start(std::function<void()> job) {
  if (started_) throw std::logic_error("BackgroundJob::start: the job before was not waited for");
  if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(job);
    running_ = true;
    error_ = nullptr;
  }
  started_ = true;
  wake_.notify_one();
}

void BackgroundJob::wait() {
  if (!started_) return;
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return !running_; });
    error.swap(error_);
  }
  started_ = false;
  if (error) std::rethrow_exception(error);
}

void BackgroundJob::loop() {
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || job_; });
      if (quit_) return;
      job.swap(job_);
    }
    std::exception_ptr error;
    try {
      job();
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = error;
      running_ = false;
    }
    done_.notify_all();
  }
}

}  // namespace multiray
