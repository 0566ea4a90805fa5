#include "device/cpu/cgroup_quota.h"

#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace multiray {

namespace {
const char* kRoot = "/sys/fs/cgroup/cpu";

bool write_file(const std::string& path, const std::string& value) {
  std::ofstream f(path);
  if (!f) return false;
  f << value;
  f.flush();
  return bool(f);
}
}  // namespace

CgroupQuota::CgroupQuota(const std::string& name, double fraction) {
  if (!(fraction > 0.0 && fraction <= 64.0))
    throw DeviceError("cpu quota must be in (0, 64] cores, got " + std::to_string(fraction));
  struct stat st;
  if (stat((std::string(kRoot) + "/cpu.cfs_quota_us").c_str(), &st) != 0)
    throw DeviceError(std::string("quota= needs the cgroup v1 cpu controller at ") + kRoot +
                      ", which this machine does not have");
  dir_ = std::string(kRoot) + "/multiray-" + std::to_string(getpid()) + "-" + name;
  if (mkdir(dir_.c_str(), 0755) != 0 && errno != EEXIST)
    throw DeviceError("quota=: cannot create " + dir_ + ": " + std::strerror(errno) +
                      " (needs root)");
  // A short period (10 ms) throttles smoothly even within one frame; with the default
  // 100 ms a frame shorter than the period could run unthrottled.
  const long period = 10000;
  if (!write_file(dir_ + "/cpu.cfs_period_us", std::to_string(period)) ||
      !write_file(dir_ + "/cpu.cfs_quota_us", std::to_string(long(period * fraction)))) {
    rmdir(dir_.c_str());
    throw DeviceError("quota=: cannot set the CPU quota in " + dir_);
  }
}

CgroupQuota::~CgroupQuota() {
  // A group can only be removed when empty; devices move their threads out before this.
  rmdir(dir_.c_str());
}

bool CgroupQuota::join_current_thread() const {
  return write_file(dir_ + "/tasks", std::to_string(long(syscall(SYS_gettid))));
}

void CgroupQuota::leave_current_thread() {
  write_file(std::string(kRoot) + "/tasks", std::to_string(long(syscall(SYS_gettid))));
}

}  // namespace multiray
