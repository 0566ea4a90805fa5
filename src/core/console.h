// Lines for people, on stdout and stderr, that never end a run. The CLI ignores SIGPIPE
// (run_cli), so a reader that has gone away (`multiray render ... | head -1`) shows up as
// a failed write; the stream is then marked closed and not written again, and the run
// goes on to write its images and stats.json. Each call writes and flushes at once, so a
// pipe sees every line as it is printed.
#pragma once

#include <cstdio>
#include <string_view>

#include <fmt/core.h>

namespace multiray {

// Writes `text` to `stream` (stdout or stderr) unless an earlier write to it failed.
// Returns false when the text did not (all) arrive.
bool write_console(std::FILE* stream, std::string_view text);

// True once a write to `stream` has failed (its reader is gone).
bool console_closed(std::FILE* stream);

// True when stderr is a terminal (progress lines are drawn only then).
bool stderr_is_tty();

template <class... Args>
void print_out(fmt::format_string<Args...> format, Args&&... args) {
  write_console(stdout, fmt::format(format, std::forward<Args>(args)...));
}

template <class... Args>
void print_err(fmt::format_string<Args...> format, Args&&... args) {
  write_console(stderr, fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace multiray
