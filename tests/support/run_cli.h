// Running the multiray binary from a test, as a user would from a shell.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace multiray::testing {

struct CliResult {
  int code = -1;    // exit code; 128 + signal if killed
  std::string out;  // stdout and stderr together
};

// Runs `binary args` with `env` (shell assignments, may be empty) in front, under a 120 s
// timeout so a hang fails the test instead of the suite.
inline CliResult run_cli(const std::string& binary, const std::string& args,
                         const std::string& env = "", int timeout_s = 120) {
  const std::string cmd =
      env + " timeout " + std::to_string(timeout_s) + " " + binary + " " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

// Peak resident memory of `binary args...` in KB (ru_maxrss of the child; stdout to
// /dev/null), -1 if it did not exit 0.
inline long peak_rss_kb(const std::string& binary, const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    std::vector<char*> argv{const_cast<char*>(binary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  rusage use{};
  if (pid < 0 || wait4(pid, &status, 0, &use) != pid) return -1;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? use.ru_maxrss : -1;
}

}  // namespace multiray::testing
