// Real CPU throttling with the cgroup v1 cpu controller (see ../shared/PLATFORM.md): a
// group with cfs_quota_us / cfs_period_us = fraction of one core; threads join it by
// writing their thread id to `tasks`. Needs root and a mounted v1 cpu controller.
#pragma once

#include <string>

namespace multiray {

class CgroupQuota {
 public:
  // Creates /sys/fs/cgroup/cpu/multiray-<pid>-<name> with the given fraction of a core
  // per period. Throws DeviceError with the reason when the machine does not allow it.
  CgroupQuota(const std::string& name, double fraction_of_core);
  ~CgroupQuota();  // moves nothing back: the group is removed once its threads exit it
  CgroupQuota(const CgroupQuota&) = delete;
  CgroupQuota& operator=(const CgroupQuota&) = delete;

  // Moves the calling thread into the group. Returns false if that failed.
  bool join_current_thread() const;
  // Moves the calling thread back to the root group.
  static void leave_current_thread();

 private:
  std::string dir_;
};

}  // namespace multiray
