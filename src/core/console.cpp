#include "core/console.h"

#include <unistd.h>

#include <atomic>
#include <mutex>

namespace multiray {

namespace {
std::atomic<bool> stdout_closed{false}, stderr_closed{false};
std::mutex console_mutex;  // lines of two threads (a progress line, a frame line) whole

std::atomic<bool>& closed_flag(std::FILE* stream) {
  return stream == stderr ? stderr_closed : stdout_closed;
}
}  // namespace

bool write_console(std::FILE* stream, std::string_view text) {
  std::atomic<bool>& closed = closed_flag(stream);
  if (closed) return false;
  std::lock_guard<std::mutex> lock(console_mutex);
  const bool ok =
      std::fwrite(text.data(), 1, text.size(), stream) == text.size() && std::fflush(stream) == 0;
  if (!ok) {
    closed = true;
    std::clearerr(stream);
  }
  return ok;
}

bool console_closed(std::FILE* stream) { return closed_flag(stream); }

bool stderr_is_tty() { return isatty(STDERR_FILENO) == 1; }

}  // namespace multiray
