#include <thread>

#include <fmt/core.h>

#include "app/commands.h"

namespace multiray::app {

Runner add_devices_command(CLI::App& app) {
  app.add_subcommand("devices", "List the devices this machine offers, with their --devices spec");
  return []() -> int {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    fmt::print("{:<8} {:<34} {:>6}  {}\n", "type", "name", "units", "spec");
    fmt::print("{:<8} {:<34} {:>6}  {}\n", "cpu", "all cores (oneTBB + Embree)", cores,
               fmt::format("cpu:threads={}", cores));
    for (unsigned c = 0; c < cores; ++c)
      fmt::print("{:<8} {:<34} {:>6}  {}\n", "cpu", fmt::format("core {}", c), 1,
                 fmt::format("cpu:threads=1:cores={}", c));
    fmt::print("\nAdd :speed=S (emulated slowdown) or :quota=Q (real cgroup throttle) to any cpu spec.\n");
    return 0;
  };
}

}  // namespace multiray::app
