// The set-up of every thread that runs a CPU device's work, in its arena or calling it.
#pragma once

#include <pthread.h>
#include <sched.h>

#include <utility>
#include <vector>

#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_scheduler_observer.h>

#include "device/cpu/cgroup_quota.h"
#include "render/accel.h"

namespace multiray {

// Prepares every thread that enters the device's arena: float mode, core pinning, quota.
class ThreadSetup : public oneapi::tbb::task_scheduler_observer {
 public:
  ThreadSetup(oneapi::tbb::task_arena& arena, std::vector<int> cores, const CgroupQuota* quota)
      : task_scheduler_observer(arena), cores_(std::move(cores)), quota_(quota) {
    observe(true);
  }
  ~ThreadSetup() override { observe(false); }

  void on_scheduler_entry(bool) override { prepare_current_thread(); }

  void prepare_current_thread() const {
    set_fast_float_mode();
    if (!cores_.empty()) {
      cpu_set_t set;
      CPU_ZERO(&set);
      for (int c : cores_) CPU_SET(c, &set);
      pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    }
    if (quota_) quota_->join_current_thread();
  }

 private:
  std::vector<int> cores_;
  const CgroupQuota* quota_;
};

}  // namespace multiray
