#include "scene/assimp_trial.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <new>

namespace multiray::detail {

namespace {

// Exit codes of the child.
constexpr int kFits = 0, kTooLarge = 3, kFailed = 4;

// This process's address space now, in bytes (/proc/self/statm's first field is pages).
uint64_t address_space_bytes() {
  unsigned long long pages = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%llu", &pages) != 1) pages = 0;
    std::fclose(f);
  }
  return pages * uint64_t(sysconf(_SC_PAGESIZE));
}

// In the child: limits the address space, reads, and ends without running the parent's
// atexit handlers or flushing its stdio buffers (_exit).
[[noreturn]] void run_child(uint64_t limit_bytes, const std::function<void()>& read) {
  rlimit lim{};
  getrlimit(RLIMIT_AS, &lim);
  rlim_t want = rlim_t(address_space_bytes() + limit_bytes);
  if (lim.rlim_max != RLIM_INFINITY && want > lim.rlim_max) want = lim.rlim_max;
  lim.rlim_cur = want;
  if (setrlimit(RLIMIT_AS, &lim) != 0) _exit(kFailed);
  try {
    read();
  } catch (const std::bad_alloc&) {
    _exit(kTooLarge);
  } catch (...) {
    _exit(kFits);  // refused by the parser: the read in-process says why
  }
  _exit(kFits);
}

}  // namespace

TrialResult trial_read(uint64_t limit_bytes, const std::function<void()>& read, int* signal) {
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t pid = fork();
  if (pid < 0) return TrialResult::fits;  // no child to spare: read in-process as before
  if (pid == 0) run_child(limit_bytes, read);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return TrialResult::fits;
  if (WIFSIGNALED(status)) {
    if (signal) *signal = WTERMSIG(status);
    return TrialResult::crashed;
  }
  return WEXITSTATUS(status) == kTooLarge ? TrialResult::too_large : TrialResult::fits;
}

}  // namespace multiray::detail
