// A Material evaluated at one surface point, as render/surface.cpp, operation for
// operation: each factor times its texture, the normal map tilting the shading normal in
// the triangle's tangent frame, and the coverage that decides alpha cut-outs.

typedef struct {
  float3 base_color;
  float metallic, roughness;  // unclamped, as SurfacePoint
  float3 ns;                  // shading normal after the normal map
} SurfacePoint;

// Emitted radiance of `m` at `uv` (the caller checks m->emissive).
float3 emission_at(const SceneData* sc, const __global Material* m, float2 uv) {
  const float3 e = load3(m->emission);
  if (m->emission_texture < 0) return e;
  return e * scene_texture(sc, m->emission_texture, uv);
}

// tilted_normal(): `tangent` is (u, sign) of the triangle.
float3 tilted_normal(const SceneData* sc, int map, float scale, float2 uv, float3 ns, float3 ng,
                     float4 tangent) {
  const float3 m = scene_texture(sc, map, uv);
  const float x = m.x * scale, y = m.y * scale;
  const float3 tangent_u = tangent.xyz;
  if ((x == 0.0f && y == 0.0f) || !(dot3(tangent_u, tangent_u) > 0.0f)) return ns;
  const float3 t = tangent_u - ns * dot3(ns, tangent_u);
  if (!(dot3(t, t) > 1e-12f)) return ns;
  const float3 tu = normalize3(t);
  const float3 b = cross3(ns, tu) * tangent.w;
  const float3 n = normalize3(tu * x + b * y + ns * fmax(m.z, 0.0f));
  return finite3(n) && dot3(n, ng) > 0.0f ? n : ns;
}

// surface_at() for scene triangle `prim`; `ns` unit, on the side of `ng`.
SurfacePoint surface_at(const SceneData* sc, const __global Material* m, float2 uv, float3 ns,
                        float3 ng, uint prim) {
  SurfacePoint sp;
  sp.base_color = load3(m->color);
  if (m->texture >= 0) sp.base_color *= scene_texture(sc, m->texture, uv);
  sp.metallic = m->metallic;
  sp.roughness = m->roughness;
  if (m->metallic_roughness_texture >= 0) {
    const float3 mr = scene_texture(sc, m->metallic_roughness_texture, uv);
    sp.roughness *= mr.y;
    sp.metallic *= mr.z;
  }
  sp.ns = ns;
  if (m->normal_texture >= 0 && sc->has_tangents)
    sp.ns = tilted_normal(sc, m->normal_texture, m->normal_scale, uv, ns, ng, sc->tangents[prim]);
  return sp;
}

// alpha_at(): opacity times the base colour texture's alpha.
float alpha_at(const SceneData* sc, const __global Material* m, float2 uv) {
  if (m->texture < 0) return m->opacity;
  return m->opacity * sample_texture_alpha(&sc->textures[m->texture], sc->texels, sc->texel_luts, uv);
}

// passes_through(): `u` is the ray's hash (ray_hash in traverse.cl).
bool passes_through(const SceneData* sc, const __global Material* m, float2 uv, float u) {
  if (m->alpha_mode == 1u) return alpha_at(sc, m, uv) < m->alpha_cutoff;
  if (m->alpha_mode == 2u) return u >= alpha_at(sc, m, uv);
  return false;
}
