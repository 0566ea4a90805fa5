// Next-event estimation's light sampling, written once for every backend: a triangle
// chosen by binary search in the power CDF (the LightSampler's table, render/lights.h),
// a point on it by Heitz's low-distortion map (sampling.h), its radiance the material's
// emission at the point's uv. SceneData provides `lights`, `light_cdf`, `light_count`,
// `materials` and `scene_shading(sc, prim)` (the triangle's uvs and material).
#ifndef MULTIRAY_RENDER_SHARED_LIGHTS_H
#define MULTIRAY_RENDER_SHARED_LIGHTS_H

#ifdef __cplusplus
#include "render/shared/sampling.h"
#include "render/shared/surface.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  mr_float3 point;
  mr_float3 normal;  // geometric, the emitting side
  mr_float3 radiance;
  float pdf_area;  // selection probability / triangle area
} LightSample;

// sc->light_count > 0. The first CDF entry greater than `u` picks the triangle.
MR_DEVICE LightSample sample_light(const SceneData* sc, float u, float u1, float u2) {
  const MR_GLOBAL LightRecord* l = &sc->lights[pick_cdf(sc->light_cdf, sc->light_count, u)];
  const mr_float3 a = load3(l->a), b = load3(l->b), c = load3(l->c);
  const mr_float2 bc = sample_triangle(u1, u2);
  LightSample s;
  s.point = triangle_point(a, b, c, bc);
  s.normal = normalize3(cross3(b - a, c - a));
  s.radiance = load3(l->radiance);
  const ShadingRecord d = scene_shading(sc, l->prim);
  const MR_GLOBAL MaterialRecord* m = &sc->materials[d.material];
  if (m->emission_texture >= 0)
    s.radiance = s.radiance * scene_texture_rgb(sc, m->emission_texture,
                                                shading_uv(&d, 1.0f - bc.x - bc.y, bc.x, bc.y));
  s.pdf_area = l->pdf_area;
  return s;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_LIGHTS_H
