// A material evaluated at one surface point, written once for every backend: each factor
// times its texture, the normal map tilting the shading normal in the triangle's tangent
// frame, and the coverage that decides alpha cut-outs.
//
// The scene is reached through the backend's SceneData (render/scene_data.h on the CPU,
// the OpenCL kernels' own struct), which provides `materials` and three accessors:
//   ShadingRecord scene_shading(const SceneData*, mr_uint prim);  // corner normals, uvs
//   TextureView scene_texture(const SceneData*, mr_int index);
//   bool scene_tangent(const SceneData*, mr_uint prim, mr_float4* tangent);  // (u, sign)
#ifndef MULTIRAY_RENDER_SHARED_SURFACE_H
#define MULTIRAY_RENDER_SHARED_SURFACE_H

#ifdef __cplusplus
#include "render/scene_data.h"
#include "render/shared/language.h"
#include "render/shared/scene_records.h"
#include "render/shared/texture.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  mr_float3 base_color;
  float metallic, roughness;  // unclamped (bsdf_params clamps them)
  mr_float3 ns;               // shading normal after the normal map
} SurfacePoint;

// The uv of triangle record `d` at barycentrics (b0, b1, b2) of its corners.
MR_DEVICE mr_float2 shading_uv(const ShadingRecord* d, float b0, float b1, float b2) {
  return MR_FLOAT2(d->uv[0].x * b0 + d->uv[1].x * b1 + d->uv[2].x * b2,
                   d->uv[0].y * b0 + d->uv[1].y * b1 + d->uv[2].y * b2);
}

MR_DEVICE mr_float3 scene_texture_rgb(const SceneData* sc, mr_int index, mr_float2 uv) {
  const TextureView t = scene_texture(sc, index);
  return texture_sample(&t, uv);
}

// Emitted radiance of `m` at `uv` (zero if it does not emit).
MR_DEVICE mr_float3 emission_at(const SceneData* sc, const MR_GLOBAL MaterialRecord* m,
                                mr_float2 uv) {
  const mr_float3 e = load3(m->emission);
  if (m->emission_texture < 0) return e;
  return e * scene_texture_rgb(sc, m->emission_texture, uv);
}

// The normal map's tangent-space normal at `uv` applied to `ns` (glTF 2.0 §3.9.3: x along
// the tangent, y along the bitangent, z along the normal; x and y scaled by `scale`);
// `ns` is kept where the map is flat or the result would face away from `ng`.
MR_DEVICE mr_float3 tilted_normal(const SceneData* sc, mr_int map, float scale, mr_float2 uv,
                                  mr_float3 ns, mr_float3 ng, mr_float4 tangent) {
  const mr_float3 m = scene_texture_rgb(sc, map, uv);
  const float x = m.x * scale, y = m.y * scale;
  const mr_float3 tangent_u = MR_XYZ(tangent);
  if ((x == 0.0f && y == 0.0f) || !(dot3(tangent_u, tangent_u) > 0.0f)) return ns;
  const mr_float3 t = tangent_u - ns * dot3(ns, tangent_u);
  if (!(dot3(t, t) > 1e-12f)) return ns;
  const mr_float3 tu = normalize3(t);
  const mr_float3 b = cross3(ns, tu) * tangent.w;
  const mr_float3 n = normalize3(tu * x + b * y + ns * mr_fmax(m.z, 0.0f));
  return finite3(n) && dot3(n, ng) > 0.0f ? n : ns;
}

// Scattering parameters of `m` at `uv` on triangle `prim`: `ns` is the interpolated
// shading normal (unit, on the side of `ng`). `base` is the base colour texture's
// footprint at `uv` when the caller has it (0: looked up here).
MR_DEVICE SurfacePoint surface_at(const SceneData* sc, const MR_GLOBAL MaterialRecord* m,
                                  mr_float2 uv, mr_float3 ns, mr_float3 ng, mr_uint prim,
                                  const TexFootprint* base) {
  SurfacePoint sp;
  sp.base_color = load3(m->color);
  if (m->texture >= 0) {
    const TextureView t = scene_texture(sc, m->texture);
    sp.base_color = sp.base_color * (base ? texture_sample_at(&t, base) : texture_sample(&t, uv));
  }
  sp.metallic = m->metallic;
  sp.roughness = m->roughness;
  if (m->metallic_roughness_texture >= 0) {
    const mr_float3 mr = scene_texture_rgb(sc, m->metallic_roughness_texture, uv);
    sp.roughness *= mr.y;
    sp.metallic *= mr.z;
  }
  sp.ns = ns;
  mr_float4 tangent;
  if (m->normal_texture >= 0 && scene_tangent(sc, prim, &tangent))
    sp.ns = tilted_normal(sc, m->normal_texture, m->normal_scale, uv, ns, ng, tangent);
  return sp;
}

// Coverage of `m` at `uv` in [0, 1]: opacity times the base colour texture's alpha.
MR_DEVICE float alpha_at(const SceneData* sc, const MR_GLOBAL MaterialRecord* m, mr_float2 uv) {
  if (m->texture < 0) return m->opacity;
  const TextureView t = scene_texture(sc, m->texture);
  return m->opacity * texture_sample_alpha(&t, uv);
}

// The number in [0, 1) that decides a `blend` cut-out: a 32-bit mix of the bits of a
// ray's origin and direction (`key`, 6 floats) and the triangle, so every device makes
// the same decision for the same ray (render/accel.cpp's filter, the OpenCL traversal).
MR_DEVICE float cutout_hash(const float key[6], mr_uint prim) {
  mr_uint h = 0x9e3779b9u ^ prim;
  for (int i = 0; i < 6; ++i) {
    h ^= mr_float_as_uint(key[i]) + 0x7f4a7c15u + (h << 6) + (h >> 2);
    h *= 0x85ebca6bu;
    h ^= h >> 13;
  }
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return (float)(h >> 8) * (1.0f / 16777216.0f);
}

// Whether a ray passes through the point of `m` at `uv`: `mask` compares the coverage
// with the cutoff, `blend` compares it with `u` (uniform in [0, 1), fixed per ray so
// that every device makes the same decision). Always false for opaque materials.
MR_DEVICE bool passes_through(const SceneData* sc, const MR_GLOBAL MaterialRecord* m, mr_float2 uv,
                              float u) {
  if (m->alpha_mode == 1u) return alpha_at(sc, m, uv) < m->alpha_cutoff;
  if (m->alpha_mode == 2u) return u >= alpha_at(sc, m, uv);
  return false;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SURFACE_H
