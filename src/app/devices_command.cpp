#include <unistd.h>

#include <thread>

#include <fmt/core.h>

#include "app/commands.h"
#include "device/device_factory.h"
#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_platform.h"
#endif

namespace multiray::app {

namespace {

std::string gib(double bytes) { return fmt::format("{:.1f} GB", bytes / double(1u << 30)); }

void print_row(const std::string& type, const std::string& name, unsigned units,
               const std::string& memory, const std::string& spec) {
  fmt::print("{:<8} {:<40} {:>6} {:>9}  {}\n", type, name, units, memory, spec);
}

}  // namespace

Runner add_devices_command(CLI::App& app) {
  app.add_subcommand("devices", "List the devices this machine offers, with their --devices spec");
  return []() -> int {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const std::string ram = gib(double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)));
    fmt::print("{:<8} {:<40} {:>6} {:>9}  {}\n", "type", "name", "units", "memory", "spec");
    print_row("cpu", "all cores (oneTBB + Embree)", cores, ram,
              fmt::format("cpu:threads={}", cores));
    for (unsigned c = 0; c < cores; ++c)
      print_row("cpu", fmt::format("core {}", c), 1, ram,
                fmt::format("cpu:threads=1:cores={}", c));
#ifdef MULTIRAY_HAS_OPENCL
    const auto cl = list_opencl_devices();
    for (const OpenClDeviceListing& d : cl)
      print_row("opencl", fmt::format("{} ({})", d.name, d.kind), d.compute_units,
                gib(double(d.memory_bytes)), fmt::format("opencl:{}", d.index));
#endif
    fmt::print(
        "\nWhat each backend runs (--integrator, --sampling) and on which scene "
        "representation:\n");
    for (const char* type : {"cpu", "opencl"}) {
      const DeviceCapabilities caps = backend_capabilities(type);
      if (caps.kernels.empty()) continue;
      auto list = [](const std::vector<std::string>& v) {
        std::string out;
        for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
        return out;
      };
      fmt::print("  {:<7} kernels: {}; sampling: {}; representation: {}\n", type,
                 list(caps.kernels), list(caps.sampling), caps.representation);
    }
    fmt::print(
        "\nAdd :speed=S (emulated slowdown) or :quota=Q (real cgroup throttle) to any cpu "
        "spec.\n");
#ifdef MULTIRAY_HAS_OPENCL
    if (cl.empty()) fmt::print("No OpenCL device found (install an ICD, e.g. pocl-opencl-icd).\n");
    fmt::print(
        "OpenCL keys: speed, tile, wg, cores. With PoCL, POCL_DEVICES=\"basic basic\" gives two "
        "independent one-core devices; POCL_MAX_PTHREAD_COUNT=N limits its pthread device.\n");
#else
    fmt::print(
        "This multiray was built without OpenCL (-DMULTIRAY_WITH_OPENCL=ON to require it).\n");
#endif
    return 0;
  };
}

}  // namespace multiray::app
