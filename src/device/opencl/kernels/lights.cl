// Next-event estimation's light sampling, as render/lights.cpp: a triangle is chosen by
// binary search in the power CDF (the LightSampler's own table, pick_cdf), a point on it
// by Heitz's low-distortion map (render/shared/sampling.h), its radiance the material's
// emission at the point's uv (emission_at, with the triangle's uvs: shading.cl's uv_at).

typedef struct {
  float3 point;
  float3 normal;  // geometric, the emitting side
  float3 radiance;
  float pdf_area;  // selection probability / triangle area
} LightSample;

// sc->light_count > 0. The first CDF entry greater than `u` picks one (pick_cdf).
LightSample sample_light(const SceneData* sc, float u, float u1, float u2) {
  const __global Light* l = &sc->lights[pick_cdf(sc->light_cdf, sc->light_count, u)];
  const float3 a = load3(l->a), b = load3(l->b), c = load3(l->c);
  const float2 bc = sample_triangle(u1, u2);
  LightSample s;
  s.point = triangle_point(a, b, c, bc);
  s.normal = normalize3(cross3(b - a, c - a));
  const __global Material* m = &sc->materials[material_of(sc, l->prim)];
  s.radiance = load3(l->radiance);
  if (m->emission_texture >= 0) {
    // LightSampler::uv_at, then emission_at.
    const float2 uv = uv_at(sc, l->prim, 1.0f - bc.x - bc.y, bc.x, bc.y);
    s.radiance = s.radiance * scene_texture(sc, m->emission_texture, uv);
  }
  s.pdf_area = l->pdf_area;
  return s;
}
