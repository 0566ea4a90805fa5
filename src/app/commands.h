// The CLI's sub-commands. Each registers its options on a CLI11 sub-app and returns the
// function that runs it (returning the process exit code).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "run/run.h"
#include "run/start_run.h"

namespace multiray::app {

using Runner = std::function<int()>;

// Adds the options shared by render and bench to `cmd`, storing into `o`.
void add_common_options(CLI::App& cmd, RunConfig& o);

// `command_line` (argv) is recorded in the run's stats.json.
Runner add_render_command(CLI::App& app, const std::vector<std::string>& command_line);
Runner add_bench_command(CLI::App& app);
Runner add_devices_command(CLI::App& app);
Runner add_simulate_command(CLI::App& app);
Runner add_view_command(CLI::App& app);

}  // namespace multiray::app
