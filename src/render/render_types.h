// The scene as the CPU kernels need it (RenderScene: Embree's BVH or the compact mesh,
// lights, shading records), and the plain types of a request and its report
// (render_settings.h, included here for the kernels' convenience).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/accel.h"
#include "render/compact_scene.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/render_settings.h"
#include "render/scene_data.h"
#include "render/scene_records.h"
#include "render/shading_data.h"
#include "scene/scene.h"

namespace multiray {

// Optional record of every ray traced, for the raw-Embree throughput benchmark.
struct RayLog {
  std::vector<Ray> closest, shadow;
};

// The scene as the CPU kernels need it: geometry, BVH and light sampler, built once.
// Two representations: full precision (Embree's BVH and a 64-byte shading record per
// triangle) or, given a compact scene, the quantized mesh and tree (compact_scene.h),
// decoded on access; lights, tangents and textures are full precision in both.
struct RenderScene {
  // `c`, when given, must outlive the RenderScene.
  explicit RenderScene(const Scene& s, const CompactScene* c = nullptr)
      : scene(s),
        compact(c),
        accel(s, compact),
        lights(s),
        environment(s),
        shading(compact ? std::vector<TriangleShading>() : build_shading_data(s)),
        tangents(build_tangents(s)),
        environment_choice_(choose_environment(s, lights, environment)) {
    for (const Material& m : s.materials) materials.push_back(material_record(m));
    for (const Texture& t : s.textures) textures.push_back(texture_view(t));
  }
  const Scene& scene;
  const CompactScene* compact;  // null at full precision
  Accel accel;
  LightSampler lights;
  EnvironmentLight environment;
  std::vector<TriangleShading> shading;   // empty with a compact scene: use shading_of()
  std::vector<TriangleTangent> tangents;  // empty without normal maps
  std::vector<MaterialRecord> materials;  // the scene's, as the integrator reads them
  std::vector<TextureView> textures;      // into the scene's textures

  // What the integrator reads (render/shared/path.h), with next-event estimation picking
  // the environment with probability `p_env` and rays leaving surfaces `eps` off them.
  SceneData scene_data(float p_env, float eps) const {
    return SceneData{materials.data(),
                     lights.records().data(),
                     lights.cdf().data(),
                     lights.pdf_by_prim().data(),
                     uint32_t(lights.records().size()),
                     textures.data(),
                     tangents.empty() ? nullptr : tangents.data(),
                     &environment.record(),
                     environment.tables().data(),
                     environment.map(),
                     compact ? nullptr : shading.data(),
                     compact,
                     p_env,
                     eps};
  }

  // The shading record of triangle `prim`: stored, or decoded from the compact mesh.
  TriangleShading shading_of(uint32_t prim) const {
    return compact ? decode_shading(*compact, prim) : shading[prim];
  }

  // Probability that next-event estimation samples the environment rather than an
  // emissive triangle: 0 or 1 when only one kind exists; with both, in proportion to an
  // estimate of the power each brings into the scene's bounding sphere, kept in
  // [0.1, 0.9] so that neither is starved when the estimate is poor.
  float environment_choice() const { return environment_choice_; }

  // Bytes this representation holds beyond the Scene: Embree's BVH (as Embree reports its
  // allocations) and the shading records, or the compact mesh and tree; tangents in both.
  uint64_t bytes() const {
    return (compact ? compact->bytes() : accel.bytes()) +
           shading.size() * sizeof(TriangleShading) + tangents.size() * sizeof(TriangleTangent);
  }

 private:
  static float choose_environment(const Scene& s, const LightSampler& lights,
                                  const EnvironmentLight& env);
  float environment_choice_;
};

}  // namespace multiray
