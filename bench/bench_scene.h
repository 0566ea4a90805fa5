// The scene and camera the path-tracing benches share (bench_throughput, progressive_noise,
// compact_bench): one place for how a bench finds its scene, lights it and looks at it.
#pragma once

#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include "scene/builders.h"
#include "scene/loaders.h"

namespace multiray::bench {

#ifdef MULTIRAY_SHARED_DATA_DIR
// Sponza from ../shared/data: the benches' default scene.
inline std::string default_bench_scene() {
  return std::string(MULTIRAY_SHARED_DATA_DIR) + "/meshes/dabrovic_sponza/sponza.obj";
}
#endif

// The scene at `path`. A path the user `given` that is missing or unreadable is refused
// with one line "TOOL: PATH: why" on stderr (nullopt); a missing default falls back to
// the built-in Cornell box, with a note (a clone without ../shared still runs).
inline std::optional<Scene> load_bench_scene(const char* tool, const std::string& path,
                                             bool given) {
  if (!std::filesystem::exists(path)) {
    if (given)
      return std::fprintf(stderr, "%s: %s: no such file\n", tool, path.c_str()), std::nullopt;
    std::fprintf(stderr, "note: %s not found; using the built-in Cornell box\n", path.c_str());
    return make_cornell_box();
  }
  try {
    return load_scene(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s: %s\n", tool, path.c_str(), e.what());
    return std::nullopt;
  }
}

// A white sky of 1 for a scene with neither sky nor emitter, so paths bounce as in use.
inline void light_if_unlit(Scene& scene) {
  bool lit = max_component(scene.environment) > 0;
  for (const Material& m : scene.materials) lit |= max_component(m.emission) > 0;
  if (!lit) scene.environment = Vec3(1.0f);
}

// The scene's first camera, else its default one for `aspect`; in Sponza, inside the
// atrium looking along the nave.
inline Camera bench_camera(const Scene& scene, float aspect) {
  if (scene.name == "sponza.obj")
    return Camera{{-10.0f, 3.0f, 0.0f}, {10.0f, 5.0f, 0.0f}, {0, 1, 0}, 60.0f};
  return !scene.cameras.empty() ? scene.cameras[0] : scene.default_camera(aspect);
}

}  // namespace multiray::bench
