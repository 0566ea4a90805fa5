// SIGINT and SIGTERM during a run: the first one asks the session to stop after the frame
// it is rendering (so the frames done and their stats.json are written and the output
// folder stays consistent); the command then exits with 128 + the signal number. A second
// signal while stopping ends the process at once, as usual.
#pragma once

#include <csignal>
#include <thread>

#include "engine/session.h"

namespace multiray {

class InterruptWatch {
 public:
  explicit InterruptWatch(Session& session);
  ~InterruptWatch();
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;

  // The signal that interrupted the run, or 0.
  int signal() const;
  const char* signal_name() const;

 private:
  std::thread watcher_;
  struct sigaction old_int_ {
  }, old_term_{};
};

}  // namespace multiray
