// The CLI's sub-commands. Each registers its options on a CLI11 sub-app and returns the
// function that runs it (returning the process exit code).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "run/run.h"

namespace multiray::app {

using Runner = std::function<int()>;

// Adds the options shared by render and bench to `cmd`, storing into `o`.
void add_common_options(CLI::App& cmd, RunConfig& o);

// The start render, bench and view share: applies --mapping to every balancer spec in
// `specs` (in place, before anything loads; bad specs reported as coming from `option`),
// builds the run of `o` into `s` (with `before_load`, and memory estimated for
// `specs.size()` lanes) and, on the master or a single process, prints its notes and
// returns a session with one lane per spec; `check`, if
// given, may refuse the built run before anything is printed; `quiet`: the notes are not
// printed (s.notes has them). On a worker
// rank of a distributed run it serves the master instead, sets `*worker_exit` to the exit
// code and returns null.
// `--balancer auto` (`spec` as given): what it picked for the built run `s`, printed once
// to stderr ("multiray: --balancer auto: hybrid (2 devices ...)") unless `quiet`; nullopt
// for any other spec.
std::optional<balance::AutoChoice> report_auto_choice(const Run& s, const std::string& spec,
                                                      const std::string& option, bool quiet);

std::unique_ptr<Session> start_run(Run& s, const RunConfig& o, std::vector<std::string>& specs,
                                   const std::string& option, int* worker_exit,
                                   const std::function<void()>& before_load = {},
                                   const std::function<void(const Run&)>& check = {},
                                   bool quiet = false);

// `command_line` (argv) is recorded in the run's stats.json.
Runner add_render_command(CLI::App& app, const std::vector<std::string>& command_line);
Runner add_bench_command(CLI::App& app);
Runner add_devices_command(CLI::App& app);
Runner add_simulate_command(CLI::App& app);
Runner add_view_command(CLI::App& app);

}  // namespace multiray::app
