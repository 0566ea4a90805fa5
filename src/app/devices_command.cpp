#include <unistd.h>

#include <algorithm>
#include <memory>
#include <thread>

#include <fmt/core.h>

#include "app/commands.h"
#include "device/device_factory.h"
#include "device/scene_memory.h"
#include "render/compact_scene.h"
#include "scene/builders.h"
#include "scene/loaders.h"
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

// `multiray devices --devices SPEC [--scene FILE]`: builds each listed device on the
// scene and prints the representation it renders from and its size (issue: memory per
// device), with the scene's full-precision and compact sizes by part.
int report_scene_memory(const std::string& scene_path, const std::string& devices) {
  const Scene scene = scene_path.empty() ? make_cornell_box() : load_scene(scene_path);
  SceneCache cache(scene);
  fmt::print("scene {}: {} triangles, {} vertices\n", scene_path.empty() ? scene.name : scene_path,
             scene.triangle_count(), scene.positions.size());
  if (scene.has_triangles()) {
    const CompactScene& c = cache.compact_scene();
    const SceneBytes full = full_precision_bytes(scene, c.bvh.nodes.size());
    const SceneBytes small = compact_bytes(c);
    fmt::print("  full precision: mesh {}, structure {}, both {}\n", format_bytes(full.mesh),
               format_bytes(full.structure), format_bytes(full.total()));
    fmt::print("  compact:        mesh {}, structure {}, both {} ({:.2f}x smaller)\n",
               format_bytes(small.mesh), format_bytes(small.structure),
               format_bytes(small.total()),
               double(full.total()) / double(std::max<size_t>(1, small.total())));
  }
  const auto built = create_devices(devices, cache);
  size_t name_width = 6;  // "device"; the column fits the longest name
  for (const auto& d : built) name_width = std::max(name_width, d->info().name.size());
  fmt::print("{:<{}} {:<16} {:>11} {:>20}\n", "device", name_width, "representation", "scene",
             "memory limit");
  for (const auto& d : built) {
    const DeviceInfo& i = d->info();
    fmt::print("{:<{}} {:<16} {:>11} {:>20}\n", i.name, name_width, i.representation,
               i.scene_bytes ? format_bytes(i.scene_bytes) : "-",
               i.memory_limit ? format_bytes(i.memory_limit) + " (emulated)" : "-");
  }
  return 0;
}

}  // namespace

Runner add_devices_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "devices",
      "List the devices this machine offers, with their --devices spec; with --devices, build "
      "those devices on a scene and report the memory each one's scene representation takes");
  auto devices = std::make_shared<std::string>();
  auto scene = std::make_shared<std::string>();
  cmd->add_option("--devices", *devices,
                  "Devices to build on the scene, as for render (e.g. "
                  "cpu,cpu:compact=1,opencl:0:compact=1:mem=256M)");
  cmd->add_option("--scene", *scene, "Mesh file for --devices (default: the Cornell box)")
      ->check(CLI::ExistingFile);
  return [devices, scene]() -> int {
    if (!devices->empty()) return report_scene_memory(*scene, *devices);
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
