// How the integrator (render/shared/) reaches this backend's scene: a triangle's shading
// record (scene_shading), a texture (scene_texture) and a tangent (scene_tangent), and
// for the traversal's cut-outs a triangle's material. At full precision they come from
// the triangle's shading record; with -DMR_COMPACT=1 they are decoded from the compact
// mesh by render/shared/compact_mesh.h (the CPU's decoding too).

#ifdef MR_COMPACT

uint material_of(const SceneData* sc, uint prim) { return compact_material(&sc->cmesh, prim); }

ShadingRecord scene_shading(const SceneData* sc, uint prim) {
  ShadingRecord d;
  compact_shading(&sc->cmesh, prim, d.normal, d.uv, &d.material);
  return d;
}

#else

uint material_of(const SceneData* sc, uint prim) { return sc->shading[prim].material; }

ShadingRecord scene_shading(const SceneData* sc, uint prim) {
  const __global StoredShading* s = &sc->shading[prim];
  ShadingRecord d;
  for (int k = 0; k < 3; ++k) {
    d.normal[k] = load3(s->normal + 3 * k);
    d.uv[k] = (float2)(s->uv[2 * k], s->uv[2 * k + 1]);
  }
  d.material = s->material;
  return d;
}

#endif

TextureView scene_texture(const SceneData* sc, int index) {
  const __global TextureRecord* t = &sc->textures[index];
  TextureView v = {sc->texels + t->offset, sc->texel_luts + 256u * t->coding,
                   sc->texel_luts + 256u, t->width, t->height};
  return v;
}

bool scene_tangent(const SceneData* sc, uint prim, float4* tangent) {
  if (!sc->has_tangents) return false;
  *tangent = sc->tangents[prim];
  return true;
}
