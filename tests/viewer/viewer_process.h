// `multiray view` started as a user would, for the viewer tests: the port it printed, and
// a clean stop (SIGINT) at the end.
#pragma once

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

namespace multiray::testing {

class ViewerProcess {
 public:
  // `launcher` goes before the program (e.g. "mpiexec -np 3 " for a --distributed view).
  explicit ViewerProcess(const std::string& args, const std::string& launcher = "") {
    int out[2];
    if (pipe(out) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    const std::string cmd =
        std::string("exec ") + launcher + MULTIRAY_BIN + " view --port 0 " + args;
    std::vector<char*> argv = {const_cast<char*>("sh"), const_cast<char*>("-c"),
                               const_cast<char*>(cmd.c_str()), nullptr};
    if (posix_spawn(&pid_, "/bin/sh", &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    FILE* f = fdopen(out[0], "r");
    char line[256];
    // "multiray: viewer at http://127.0.0.1:PORT/ ..." ("http://[::1]:PORT/" for IPv6)
    if (f && fgets(line, sizeof line, f)) {
      const std::string s(line);
      const auto colon = s.rfind(':', s.find("/ "));
      if (colon != std::string::npos) port_ = std::atoi(s.c_str() + colon + 1);
      const auto at = s.find("http://");
      if (at != std::string::npos) url_ = s.substr(at, s.find(' ', at) - at);
    }
    out_ = f;
  }
  ~ViewerProcess() { stop(); }
  int port() const { return port_; }
  const std::string& url() const { return url_; }
  // SIGINT, then the exit code (128 + SIGINT expected). A viewer that has not exited 30 s
  // later is killed and reported as -1, so that a lost Ctrl-C fails the test in seconds
  // instead of hanging it until ctest's timeout.
  int stop() {
    if (pid_ <= 0) return code_;
    kill(pid_, SIGINT);
    int status = 0;
    bool exited = false;
    for (int i = 0; i < 3000 && !exited; ++i) {
      exited = waitpid(pid_, &status, WNOHANG) == pid_;
      if (!exited) usleep(10000);
    }
    if (!exited) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      pid_ = -1;
      if (out_) fclose(out_), out_ = nullptr;
      return code_ = -1;
    }
    pid_ = -1;
    if (out_) fclose(out_), out_ = nullptr;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return code_;
  }

 private:
  pid_t pid_ = -1;
  int port_ = 0, code_ = -1;
  std::string url_;
  FILE* out_ = nullptr;
};

}  // namespace multiray::testing
