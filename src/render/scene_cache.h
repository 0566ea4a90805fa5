// The immutable Scene and the representations devices build from it. A device asks for
// the representation it needs by name; the first asker builds it, the others share it
// (every CPU device uses one Embree BVH). Later representations — a compact mesh for a
// memory-limited device, a volume with its block histograms, a copy on a remote rank —
// are more names here, not more constructor arguments. The bit-identical guarantee holds
// per (device type, representation).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "render/compact_scene.h"
#include "render/render_types.h"
#include "scene/scene.h"

namespace multiray {

class SceneCache {
 public:
  // `scene` must outlive the cache and every device created from it.
  explicit SceneCache(const Scene& scene) : scene_(scene) {}
  SceneCache(const SceneCache&) = delete;
  SceneCache& operator=(const SceneCache&) = delete;

  const Scene& scene() const { return scene_; }

  // The representation called `key`, built by `build(scene)` on first use and shared
  // afterwards; every call for one key must ask for the same type T. Thread-safe; a
  // build that throws leaves nothing cached.
  template <class T>
  const T& get(const std::string& key,
               const std::function<std::unique_ptr<T>(const Scene&)>& build) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = built_.find(key);
    if (it == built_.end()) {
      std::shared_ptr<T> made(build(scene_));
      it = built_.emplace(key, std::shared_ptr<const void>(made, made.get())).first;
    }
    return *static_cast<const T*>(it->second.get());
  }

  // The Embree BVH, light sampler and shading records the CPU kernels trace
  // (representation "embree").
  const RenderScene& embree() {
    return get<RenderScene>("embree",
                            [](const Scene& s) { return std::make_unique<RenderScene>(s); });
  }
  // The quantized mesh and tree (render/compact_scene.h), shared by every device that
  // asked for compact=1 (representation "compact-scene").
  const CompactScene& compact_scene() {
    return get<CompactScene>("compact-scene", [](const Scene& s) {
      return std::make_unique<CompactScene>(build_compact_scene(s));
    });
  }
  // What the CPU kernels trace with compact=1 (representation "compact").
  const RenderScene& compact() {
    const CompactScene* c = &compact_scene();
    return get<RenderScene>("compact",
                            [c](const Scene& s) { return std::make_unique<RenderScene>(s, c); });
  }
  const RenderScene& mesh(bool compact_representation) {
    return compact_representation ? compact() : embree();
  }

  // Names of the representations built so far.
  std::vector<std::string> built() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [key, value] : built_) out.push_back(key);
    return out;
  }

 private:
  const Scene& scene_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const void>> built_;
};

}  // namespace multiray
