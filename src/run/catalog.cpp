#include "run/catalog.h"

#include <unistd.h>

#include <algorithm>
#include <thread>

#include <fmt/core.h>

#include "core/error.h"
#include "device/device_factory.h"
#include "distributed/pixel_codec.h"
#include "render/compact_scene.h"
#include "render/kernel.h"
#include "render/scene_cache.h"
#include "run/run.h"
#include "scene/builders.h"
#include "scene/loaders.h"
#include "volume/transfer_function.h"
#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_platform.h"
#endif

namespace multiray {

std::vector<Choice> kernel_choices() {
  std::vector<Choice> out;
  for (const KernelEntry& e : cpu_kernels()) out.push_back({e.name, e.help});
  return out;
}

std::vector<std::string> transfer_presets() { return transfer_preset_names(); }

bool zstd_results_available() { return remote::zstd_available(); }

const std::vector<BackendEntry>& device_backend_choices() { return device_backends(); }

std::string device_keys_help() {
  std::string out;
  for (const BackendEntry& b : device_backends()) {
    std::string keys;
    for (const BackendParam& p : b.params)
      keys += (keys.empty() ? "" : ", ") + p.key + " (" + p.values +
              (p.fallback.empty() ? "" : ", default " + p.fallback) + "): " + p.help;
    out += (out.empty() ? "" : ". ") + b.name + " (" + b.help + ") keys: " + keys;
  }
  return out;
}

Offer offered_devices() {
  Offer offer;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t ram = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  offer.devices.push_back({"cpu", "all cores (oneTBB + Embree)", cores, ram,
                           fmt::format("cpu:threads={}", cores), ""});
  for (unsigned c = 0; c < cores; ++c)
    offer.devices.push_back(
        {"cpu", fmt::format("core {}", c), 1, ram, fmt::format("cpu:threads=1:cores={}", c), ""});
#ifdef MULTIRAY_HAS_OPENCL
  offer.opencl_built = true;
  for (const OpenClDeviceListing& d : list_opencl_devices())
    offer.devices.push_back({"opencl", fmt::format("{} ({})", d.name, d.kind), d.compute_units,
                             d.memory_bytes, fmt::format("opencl:{}", d.index),
                             fmt::format("platform {}, driver {}", d.platform, d.driver)});
#endif
  for (const char* type : {"cpu", "opencl"}) {
    DeviceCapabilities caps = backend_capabilities(type);
    if (!caps.kernels.empty()) offer.backends.emplace_back(type, std::move(caps));
  }
  return offer;
}

SceneMemory scene_memory(const std::string& scene_path, const std::string& devices,
                         double max_memory) {
  RunConfig o;
  o.scene_path = scene_path;
  const double need = estimate_memory(o, 0, 0, 0, 1).total();  // the scene alone
  const auto parts = [need](double images) {
    return fmt::format("{:.1f} GB of scene", need / 1e9) +
           (images > 0 ? fmt::format(", {:.1f} GB of decoded images", images / 1e9) : "");
  };
  if (need > max_memory) throw InputError(memory_refusal(need, parts(0), max_memory));
  const Scene scene = scene_path.empty()
                          ? make_cornell_box()
                          : load_scene(scene_path, memory_guarded_load(need, max_memory, parts));
  SceneCache cache(scene);
  SceneMemory m;
  m.scene_name = scene_path.empty() ? scene.name : scene_path;
  m.triangles = scene.triangle_count();
  m.vertices = scene.positions.size();
  m.has_triangles = scene.has_triangles();
  if (m.has_triangles) {
    const CompactScene& c = cache.compact_scene();
    const SceneBytes full = full_precision_bytes(scene, c.bvh.nodes.size());
    const SceneBytes small = compact_bytes(c);
    m.full_mesh = full.mesh, m.full_structure = full.structure;
    m.compact_mesh = small.mesh, m.compact_structure = small.structure;
  }
  for (const auto& d : create_devices(devices, cache)) m.devices.push_back(d->info());
  return m;
}

}  // namespace multiray
