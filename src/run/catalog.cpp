#include "run/catalog.h"

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
    out += (out.empty() ? "" : ". ") + b.name + " (" + b.help + (b.built ? "" : "; not built") +
           ") keys: " + keys;
    if (!b.notes.empty()) out += ". " + b.notes;
  }
  return out;
}

namespace {
std::string joined(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& s : list) out += (out.empty() ? "" : ", ") + s;
  return out;
}
}  // namespace

std::string kernels_by_backend_help() {
  std::string out;
  for (const BackendEntry& b : device_backends())
    if (b.built)
      out += (out.empty() ? "" : "; ") + b.name + " runs " +
             joined(backend_capabilities(b.name).kernels);
  return out;
}

std::string shadow_catcher_backends() {
  std::vector<std::string> names;
  for (const BackendEntry& b : device_backends())
    if (backend_capabilities(b.name).shadow_catcher) names.push_back(b.name);
  return names.empty() ? "no" : joined(names);
}

Offer offered_devices() {
  Offer offer;
  for (const BackendEntry& b : device_backends()) {
    OfferedBackend o{b.name,  b.help, b.built, b.not_built, backend_capabilities(b.name),
                     b.notes, ""};
    if (b.built && b.offer) {
      const std::vector<OfferedDevice> found = b.offer();
      offer.devices.insert(offer.devices.end(), found.begin(), found.end());
      if (found.empty()) o.none_found = b.none_found;
    }
    offer.backends.push_back(std::move(o));
  }
  return offer;
}

AutoDevices auto_devices(const std::vector<OfferedDevice>& offered) {
  AutoDevices a{"cpu:threads=0", ""};
  std::vector<std::string> contend;
  for (const OfferedDevice& d : offered) {
    if (d.type == "cpu") continue;  // the cores: the one cpu device above
    if (!d.host_cores)
      a.devices += "," + d.spec;
    else
      contend.push_back(d.spec + " (" + d.name + ")");
  }
  if (!contend.empty()) {
    a.note = "--devices auto: not using ";
    for (size_t i = 0; i < contend.size(); ++i) {
      if (i > 0) a.note += ", ";
      a.note += contend[i];
    }
    a.note += contend.size() > 1 ? ": each computes" : ": it computes";
    a.note += " on the cores the cpu device already uses (add one with --devices cpu,";
    a.note += contend.front().substr(0, contend.front().find(' '));
    a.note += ")";
  }
  return a;
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
