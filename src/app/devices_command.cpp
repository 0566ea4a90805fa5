#include <unistd.h>

#include <algorithm>
#include <memory>
#include <thread>

#include <fmt/core.h>

#include "app/commands.h"
#include "core/console.h"
#include "run/catalog.h"
#include "util/parse.h"

namespace multiray::app {

namespace {

std::string gib(double bytes) { return fmt::format("{:.1f} GB", bytes / double(1u << 30)); }

void print_row(const std::string& type, const std::string& name, unsigned units,
               const std::string& memory, const std::string& spec) {
  print_out("{:<8} {:<40} {:>6} {:>9}  {}\n", type, name, units, memory, spec);
}

// `multiray devices --devices SPEC [--scene FILE]`: builds each listed device on the
// scene and prints the representation it renders from and its size (issue: memory per
// device), with the scene's full-precision and compact sizes by part.
int report_scene_memory(const std::string& scene_path, const std::string& devices,
                        double max_memory) {
  const SceneMemory m = scene_memory(scene_path, devices, max_memory);
  print_out("scene {}: {} triangles, {} vertices\n", m.scene_name, m.triangles, m.vertices);
  if (m.has_triangles) {
    const uint64_t full = m.full_mesh + m.full_structure;
    const uint64_t small = m.compact_mesh + m.compact_structure;
    print_out("  full precision: mesh {}, structure {}, both {}\n", format_bytes(m.full_mesh),
              format_bytes(m.full_structure), format_bytes(full));
    print_out("  compact:        mesh {}, structure {}, both {} ({:.2f}x smaller)\n",
              format_bytes(m.compact_mesh), format_bytes(m.compact_structure), format_bytes(small),
              double(full) / double(std::max<uint64_t>(1, small)));
  }
  size_t name_width = 6;  // "device"; the column fits the longest name
  for (const DeviceInfo& i : m.devices) name_width = std::max(name_width, i.name.size());
  print_out("{:<{}} {:<16} {:>11} {:>20}\n", "device", name_width, "representation", "scene",
            "memory limit");
  for (const DeviceInfo& i : m.devices)
    print_out("{:<{}} {:<16} {:>11} {:>20}\n", i.name, name_width, i.representation,
              i.scene_bytes ? format_bytes(i.scene_bytes) : "-",
              i.memory_limit ? format_bytes(i.memory_limit) + " (emulated)" : "-");
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
  auto max_memory = std::make_shared<std::string>("auto");
  cmd->add_option("--max-memory", *max_memory,
                  "With --scene: refuse a scene estimated to need more memory than this: auto "
                  "(half of physical memory) or a size such as 8G or 512M")
      ->capture_default_str();
  return [devices, scene, max_memory]() -> int {
    if (!devices->empty())
      return report_scene_memory(*scene, *devices, parse_memory_limit(*max_memory));
    const Offer offer = offered_devices();
    print_out("{:<8} {:<40} {:>6} {:>9}  {}\n", "type", "name", "units", "memory", "spec");
    for (const OfferedDevice& d : offer.devices)
      print_row(d.type, d.name, d.units, gib(double(d.memory_bytes)), d.spec);
    for (const OfferedDevice& d : offer.devices)
      if (!d.driver.empty()) print_out("  {}: {}\n", d.spec, d.driver);
    const AutoDevices chosen = auto_devices(offer.devices);
    print_out("\n--devices auto (the default) is {}{}\n", chosen.devices,
              chosen.note.empty() ? "" : "; " + chosen.note.substr(chosen.note.find("not using")));
    print_out(
        "\nWhat each backend runs (--integrator, --sampling) and on which scene "
        "representation:\n");
    auto list = [](const std::vector<std::string>& v) {
      std::string out;
      for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
      return out;
    };
    for (const OfferedBackend& b : offer.backends)
      if (b.built)
        print_out("  {:<7} kernels: {}; sampling: {}; representation: {}\n", b.name,
                  list(b.caps.kernels), list(b.caps.sampling), b.caps.representation);
    print_out("\nKeys of each backend (TYPE:KEY=VALUE:...):\n");
    for (const BackendEntry& b : device_backend_choices()) {
      print_out("  {}: {}\n", b.name, b.help);
      for (const BackendParam& p : b.params)
        print_out("    {:<11} {:<12} {}{}\n", p.key, p.values, p.help,
                  p.fallback.empty() ? "" : " (default " + p.fallback + ")");
    }
    // What each backend says of itself: not built (and how to build it), no device found
    // (and what to install), its notes.
    for (const OfferedBackend& b : offer.backends) {
      if (!b.built) {
        print_out("{}: {}.\n", b.name, b.not_built);
        continue;
      }
      if (!b.none_found.empty()) print_out("{}\n", b.none_found);
      if (!b.notes.empty()) print_out("{}.\n", b.notes);
    }
    return 0;
  };
}

}  // namespace multiray::app
