// The CPU's SceneData: what the integrator written once in render/shared/ (path.h,
// surface.h, lights.h, sky.h) reads of the scene, as plain pointers into RenderScene's
// records (RenderScene::scene_data). An OpenCL device builds a struct of the same fields
// from its buffers (kernels/path_tracer.cl). The three accessors below are the part that
// differs by backend: how a triangle's shading record, a texture and a tangent are found.
#pragma once

#include <cstdint>

#include "render/shading_data.h"
#include "render/shared/scene_records.h"
#include "render/shared/texture.h"

namespace multiray {

struct SceneData {
  const MaterialRecord* materials;
  const LightRecord* lights;
  const float* light_cdf;          // light_count entries, last = 1
  const float* light_pdf_by_prim;  // per scene triangle
  uint32_t light_count;
  const TextureView* textures;      // per scene texture
  const TriangleTangent* tangents;  // per triangle; null without normal maps
  const SkyRecord* sky;
  const float* sky_tables;         // the map's sampling tables at sky's offsets
  const float* sky_map;            // the map's radiance, 3 floats a pixel (null without a map)
  const TriangleShading* shading;  // full precision (null with a compact scene)
  const CompactScene* compact;     // null at full precision
  float p_env;  // probability that next-event estimation samples the environment
  float eps;    // ray-origin offset
};

inline ShadingRecord scene_shading(const SceneData* sc, uint32_t prim) {
  return sc->compact ? decode_shading(*sc->compact, prim) : sc->shading[prim];
}

inline TextureView scene_texture(const SceneData* sc, int32_t index) {
  return sc->textures[index];
}

inline bool scene_tangent(const SceneData* sc, uint32_t prim, mr_float4* tangent) {
  if (sc->tangents == nullptr) return false;
  const TriangleTangent& t = sc->tangents[prim];
  *tangent = mr_float4{t.u.x, t.u.y, t.u.z, t.sign};
  return true;
}

}  // namespace multiray
