// --help in sections (app/help_groups.h): every option of render, bench and view is in one,
// so a new option cannot land in an unsorted list at the end.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/commands.h"
#include "app/help_groups.h"

namespace help_groups_test {

using multiray::app::help_group;

TEST(HelpGroups, EveryOptionOfRenderBenchAndViewHasASection) {
  CLI::App app;
  multiray::app::add_render_command(app, {"multiray", "render"});
  multiray::app::add_bench_command(app);
  multiray::app::add_view_command(app);
  for (const char* name : {"render", "bench", "view"}) {
    CLI::App* cmd = app.get_subcommand(name);
    multiray::app::group_options(*cmd);
    size_t checked = 0;
    for (const CLI::Option* opt : cmd->get_options()) {
      if (opt->get_lnames().empty() || opt->get_lnames().front() == "help") continue;
      const std::string option = "--" + opt->get_lnames().front();
      EXPECT_NE(help_group(option), "") << name << " " << option << " has no section";
      EXPECT_EQ(opt->get_group(), help_group(option)) << option;
      ++checked;
    }
    EXPECT_GT(checked, 40u) << name;
  }
}

}  // namespace help_groups_test
