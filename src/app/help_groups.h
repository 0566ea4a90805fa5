// The sections of a command's --help (issue 32: 67 options in one flat list). Each option
// is named once in a table in help_groups.cpp; tests/cli/friendly_cli_test.cpp checks that
// no option of render, bench or view is left outside a section, so a new option must be
// placed when it is added.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace multiray::app {

// The section `option_name` (its long name, e.g. "--spp") belongs to, or "" if none.
std::string help_group(const std::string& option_name);

// Puts every option of `cmd` that the table names into its section.
void group_options(CLI::App& cmd);

// For the short --help: hides every option but the common ones (the first run's) and says
// in the footer how many more `--help-all` shows.
void hide_uncommon_options(CLI::App& cmd);

}  // namespace multiray::app
