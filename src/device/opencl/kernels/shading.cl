// How the integrator (render/shared/) reaches this backend's scene: a triangle's shading
// record (scene_shading), a texture (scene_texture) and a tangent (scene_tangent), and
// for the traversal's cut-outs a triangle's material and uv. At full precision they come
// from the triangle's shading record; with -DMR_COMPACT=1 they are decoded from the
// compact mesh with render/shared/compact.h (the CPU's decoding, decode_shading).

#ifdef MR_COMPACT

// Vertex k of a triangle (faces are bit-packed) and its position.
uint compact_vertex(const SceneData* sc, uint prim, int k) {
  return compact_read_bits(sc->indices, 3 * (ulong)prim + (ulong)k, sc->compact->widths & 0xffu);
}
float3 compact_corner(const SceneData* sc, uint prim, int k) {
  const __global CompactInfo* g = sc->compact;
  const __global ushort* q = &sc->qpos[3 * (size_t)compact_vertex(sc, prim, k)];
  return compact_decode_position(load3(g->origin), g->cell, g->step, sc->cells, q[0],
                                 (uint)q[1] | (uint)q[2] << 16);
}

// Corner k's uv: the triangle's shifts and the vertex's codes (render/shared/compact.h);
// zero without uvs, as CompactMesh::uv (their buffer is then one placeholder byte: reading
// it was out of bounds, which Oclgrind reported and a GPU may fault on).
float2 compact_uv(const SceneData* sc, uint prim, int k) {
  const __global CompactInfo* g = sc->compact;
  if (!g->has_uvs) return (float2)(0.0f);
  const __global ushort* q = &sc->quvs[2 * (size_t)compact_vertex(sc, prim, k)];
  const uint bits_u = (g->widths >> 16) & 0xffu, bits_v = g->widths >> 24;
  const uint entry = compact_read_bits(sc->uv_shifts, prim, bits_u + bits_v);
  return (float2)(compact_decode_uv(compact_uv_shift(entry, bits_u, g->uv_shift_base[0], 0u), q[0],
                                    g->uv_period_log2[0], g->uv_step[0]),
                  compact_decode_uv(compact_uv_shift(entry, bits_u, g->uv_shift_base[1], 1u), q[1],
                                    g->uv_period_log2[1], g->uv_step[1]));
}

uint material_of(const SceneData* sc, uint prim) {
  return compact_read_bits(sc->material_ids, prim, (sc->compact->widths >> 8) & 0xffu);
}

// Corner normals; the face normal for a mesh without normals.
ShadingRecord scene_shading(const SceneData* sc, uint prim) {
  ShadingRecord d;
  float3 face = (float3)(0.0f);
  if (!sc->compact->has_normals) {
    const float3 p0 = compact_corner(sc, prim, 0);
    face = normalize3(cross3(compact_corner(sc, prim, 1) - p0, compact_corner(sc, prim, 2) - p0));
  }
  for (int k = 0; k < 3; ++k) {
    d.normal[k] = sc->compact->has_normals
                      ? compact_decode_normal(sc->qnormals[compact_vertex(sc, prim, k)])
                      : face;
    d.uv[k] = compact_uv(sc, prim, k);
  }
  d.material = material_of(sc, prim);
  return d;
}

#else

uint material_of(const SceneData* sc, uint prim) { return sc->shading[prim].material; }

ShadingRecord scene_shading(const SceneData* sc, uint prim) {
  const __global Shading* s = &sc->shading[prim];
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
