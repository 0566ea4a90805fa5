// One job at a time on a thread of its own, for work that may run beside the next frame's
// rendering (Session::set_denoise_overlap: the denoiser of frame N while frame N+1
// renders). The owner starts a job, goes on with its own work, and waits for the job
// before it reads what the job wrote or starts another; an exception the job threw is
// thrown again by wait(). Not a pool: the jobs keep their order because there is never
// more than one.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace multiray {

class BackgroundJob {
 public:
  BackgroundJob() = default;
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  // Waits for the running job (its exception is dropped) and ends the thread.
  ~BackgroundJob();

  // Runs `job` on the thread (started on the first call). The job before must have been
  // waited for: std::logic_error otherwise.
  void start(std::function<void()> job);
  // Returns once no job runs; rethrows the exception of the job that just ended, if any.
  void wait();
  // A job was started and not yet waited for.
  bool started() const { return started_; }

 private:
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> job_;  // the job to run; empty once taken
  bool running_ = false;       // a job is set or running
  bool quit_ = false;
  bool started_ = false;  // on the owner's thread only
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace multiray
