// The multiray command line (app/cli.h): parse, dispatch, exit codes.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <oneapi/tbb/global_control.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/help_groups.h"
#include "core/console.h"
#include "core/error.h"
#include "study/stats_json.h"
#include "util/nearest.h"

namespace multiray::app {

namespace {
// " (did you mean --spp?)" when an argument the parsed command did not expect is within
// two edits of one of its long options (one edit, or fewer than half its length); else "".
std::string did_you_mean(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    for (const std::string& extra : sub->remaining()) {
      if (extra.rfind("--", 0) != 0) continue;
      const std::string name = extra.substr(2, extra.find('=') - 2);
      std::vector<std::string> options;
      for (const CLI::Option* opt : sub->get_options())
        for (const std::string& candidate : opt->get_lnames()) options.push_back(candidate);
      const std::string best = nearest_name(name, options);
      if (!best.empty()) return " (did you mean --" + best + "?)";
    }
  }
  return "";
}

// The first word when it names no command: one line with the nearest command (within two
// edits) and the list; "" when it is an option or a command.
std::string unknown_command(const CLI::App& app, const std::string& word) {
  if (word.empty() || word[0] == '-') return "";
  std::string names;
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == word) return "";
    if (!names.empty()) names += ", ";
    names += sub->get_name();
    commands.push_back(sub->get_name());
  }
  const std::string best = nearest_name(word, commands);
  std::string line = "unknown command '" + word + "'";
  if (!best.empty()) line += " (did you mean " + best + "?)";
  return line + "; the commands: " + names + ", help";
}
}  // namespace

int run_cli(int argc, char** argv, const CliHooks& hooks) {
  // A reader that goes away (`multiray render ... | head -1`) must not end the run by
  // SIGPIPE before its files are written: writes to it fail instead (core/console.h).
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App app{
      "multiray: a ray tracer that splits every frame across CPU cores and other devices and "
      "balances the work so they all finish together.\n\nExamples:\n"
      "  multiray render --res 640x360 --spp 16 -o render.png\n"
      "  multiray render scene.gltf --frames 100 --camera-path orbit --devices "
      "cpu:threads=1:cores=0,cpu:threads=1:cores=1\n"
      "  multiray bench --devices cpu:threads=1,cpu:threads=1:speed=0.33 --frames 100 "
      "--camera-path orbit --json bench.json --report report\n"
      "  multiray render --trace run.trace --devices cpu,cpu:speed=0.5 --frames 30\n"
      "  multiray simulate run.trace --devices 2,16,256 --link wifi --plot scaling.svg\n"
      "  multiray devices\n",
      "multiray"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("multiray ") + study::kVersion);
  Runner render = add_render_command(app, std::vector<std::string>(argv, argv + argc));
  Runner bench = add_bench_command(app);
  Runner devices = add_devices_command(app);
  Runner simulate = add_simulate_command(app);
  Runner view = add_view_command(app);
  for (const char* name : {"render", "bench", "view"}) group_options(*app.get_subcommand(name));
  // `multiray help [COMMAND]`, as git and cargo have it: the same as --help.
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "help") {
    args.erase(args.begin());
    args.resize(std::min<size_t>(args.size(), 1));
    args.push_back("--help");
  }
  // --help shows the common options; --help-all every one. (Hidden only for help: an
  // option in no group loses its name in CLI11's parse errors.)
  const auto all = std::find(args.begin(), args.end(), "--help-all");
  if (all != args.end())
    *all = "--help";
  else if (std::find(args.begin(), args.end(), "--help") != args.end() ||
           std::find(args.begin(), args.end(), "-h") != args.end())
    for (const char* name : {"render", "bench", "view"})
      hide_uncommon_options(*app.get_subcommand(name));
  if (!args.empty()) {
    const std::string unknown = unknown_command(app, args[0]);
    if (!unknown.empty()) {
      if (!hooks.quiet) print_err("multiray: error: {} (see multiray --help)\n", unknown);
      return 2;
    }
  }
  try {
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last first
    app.parse(args);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (!hooks.quiet)
      print_err("multiray: error: {}{} (see multiray --help)\n", e.what(), did_you_mean(app));
    return 2;
  }
  if (hooks.skip && hooks.skip(app)) return -1;
  try {
    if (app.got_subcommand("render")) return render();
    if (app.got_subcommand("bench")) return bench();
    if (app.got_subcommand("devices")) return devices();
    if (app.got_subcommand("simulate")) return simulate();
    if (app.got_subcommand("view")) return view();
  } catch (const QuietExit& e) {  // a worker rank; the master said why
    return e.code;
  } catch (const InputError& e) {
    if (!hooks.quiet) print_err("multiray: error: {}\n", e.what());
    return 2;
  } catch (const DeviceError& e) {
    if (!hooks.quiet) print_err("multiray: device error: {}\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    if (hooks.internal_error)
      hooks.internal_error(e.what());
    else if (!hooks.quiet)
      print_err("multiray: internal error: {}\n", e.what());
    return 4;
  }
  return 0;
}

}  // namespace multiray::app
