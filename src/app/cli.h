// The multiray command line as one function: parse, dispatch to a sub-command, map
// errors to exit codes (0 ok, 2 bad input, 3 device failure, 4 internal error). main()
// and the command-line fuzzer both call it.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace multiray::app {

struct CliHooks {
  // After parsing, before running: return true to skip the run (exit code -1).
  std::function<bool(CLI::App&)> skip;
  // Called with the message of an internal error (exit code 4); default: print it.
  std::function<void(const char* what)> internal_error;
  bool quiet = false;  // no error lines on stderr
};

int run_cli(int argc, char** argv, const CliHooks& hooks = {});

}  // namespace multiray::app
