#include "run/interrupt.h"

#include <atomic>
#include <chrono>

namespace multiray {

namespace {
volatile std::sig_atomic_t g_signal = 0;
std::atomic<bool> g_watching{false};

void on_signal(int sig) {
  if (g_signal != 0) {  // a second signal: give up at once
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
  g_signal = sig;
}
}  // namespace

InterruptWatch::InterruptWatch(Session& session) {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
  g_watching = true;
  // The handler only sets a flag; this thread turns it into a stop request.
  watcher_ = std::thread([&session] {
    while (g_watching) {
      if (g_signal != 0) {
        session.request_stop();
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
}

InterruptWatch::~InterruptWatch() {
  g_watching = false;
  if (watcher_.joinable()) watcher_.join();
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int InterruptWatch::signal() const { return int(g_signal); }

const char* InterruptWatch::signal_name() const {
  return g_signal == SIGINT ? "SIGINT" : g_signal == SIGTERM ? "SIGTERM" : "none";
}

}  // namespace multiray
