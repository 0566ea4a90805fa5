// Running the multiray binary from a test, as a user would from a shell.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

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

}  // namespace multiray::testing
