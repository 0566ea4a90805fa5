// What the shading reads of a scene triangle: its material, and its normals and uvs at a
// point given by barycentrics. At full precision they come from the triangle's shading
// record; with -DMR_COMPACT=1 they are decoded from the compact mesh on access, with the
// decoding of render/shared/compact.h (the CPU's, through compact_quantize.h) and
// render/shading_data.cpp (decode_shading), so the decoded values are the CPU's.

#ifdef MR_COMPACT

// A vertex: its cell-index table entry and offsets (render/shared/compact.h).
float3 compact_position(const SceneData* sc, uint vertex) {
  const __global CompactInfo* g = sc->compact;
  const __global ushort* q = &sc->qpos[3 * (size_t)vertex];
  return compact_decode_position((float3)(g->origin[0], g->origin[1], g->origin[2]), g->cell,
                                 g->step, sc->cells, q[0], (uint)q[1] | (uint)q[2] << 16);
}

// Vertex k of a triangle: the faces are bit-packed (render/compact_packed.h).
uint compact_vertex(const SceneData* sc, uint prim, int k) {
  return compact_read_bits(sc->indices, 3 * (ulong)prim + (ulong)k, sc->compact->widths & 0xffu);
}

float3 compact_corner(const SceneData* sc, uint prim, int k) {
  return compact_position(sc, compact_vertex(sc, prim, k));
}

float3 compact_normal(uint code) { return compact_decode_normal(code); }

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

// The uv at barycentrics (b0, b1, b2) of the triangle's vertices 0, 1, 2.
float2 uv_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const float2 a = compact_uv(sc, prim, 0), b = compact_uv(sc, prim, 1), c = compact_uv(sc, prim, 2);
  return (float2)(a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2);
}

// The interpolated (unnormalised) shading normal; the face normal for a mesh without
// normals, as decode_shading.
float3 normal_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const uint idx[3] = {compact_vertex(sc, prim, 0), compact_vertex(sc, prim, 1),
                       compact_vertex(sc, prim, 2)};
  if (!sc->compact->has_normals) {
    const float3 p0 = compact_position(sc, idx[0]);
    const float3 face =
        normalize3(cross3(compact_position(sc, idx[1]) - p0, compact_position(sc, idx[2]) - p0));
    return face * b0 + face * b1 + face * b2;
  }
  return compact_normal(sc->qnormals[idx[0]]) * b0 + compact_normal(sc->qnormals[idx[1]]) * b1 +
         compact_normal(sc->qnormals[idx[2]]) * b2;
}

#else

uint material_of(const SceneData* sc, uint prim) { return sc->shading[prim].material; }

float2 uv_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const __global Shading* d = &sc->shading[prim];
  return (float2)(d->uv[0] * b0 + d->uv[2] * b1 + d->uv[4] * b2,
                  d->uv[1] * b0 + d->uv[3] * b1 + d->uv[5] * b2);
}

float3 normal_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const __global Shading* d = &sc->shading[prim];
  return load3(d->normal) * b0 + load3(d->normal + 3) * b1 + load3(d->normal + 6) * b2;
}

#endif
