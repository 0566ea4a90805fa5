// What the shading reads of a scene triangle: its material, and its normals and uvs at a
// point given by barycentrics. At full precision they come from the triangle's shading
// record; with -DMR_COMPACT=1 they are decoded from the compact mesh on access, with the
// arithmetic of render/compact_quantize.h (decode_position, decode_normal, decode_uv) and
// render/shading_data.cpp (decode_shading), so the decoded values are the CPU's.

#ifdef MR_COMPACT

// decode_position(): the cell index (divided by multiplies, see division_magic), then
// three 10-bit offsets inside the cell.
float3 compact_position(const SceneData* sc, uint vertex) {
  const __global CompactInfo* g = sc->compact;
  const __global ushort* q = &sc->qpos[3 * (size_t)vertex];
  const uint cell = q[0];
  const uint off = (uint)q[1] | (uint)q[2] << 16;
  const uint cz = g->magic_n01 == 0u ? cell : mul_hi(cell, g->magic_n01);
  const uint rest = cell - cz * (g->n[0] * g->n[1]);
  const uint cy = g->magic_n0 == 0u ? rest : mul_hi(rest, g->magic_n0);
  const uint cx = rest - cy * g->n[0];
  const float k = 1.0f / 1023.0f;
  return (float3)(g->origin[0] + g->cell * ((float)cx + (float)(off & 1023u) * k),
                  g->origin[1] + g->cell * ((float)cy + (float)((off >> 10) & 1023u) * k),
                  g->origin[2] + g->cell * ((float)cz + (float)((off >> 20) & 1023u) * k));
}

float3 compact_corner(const SceneData* sc, uint prim, int k) {
  return compact_position(sc, sc->indices[3 * (size_t)prim + (size_t)k]);
}

// decode_normal(): the octahedral code, 8 bits of u in the low byte and 8 of v in the high.
float3 compact_normal(uint code) {
  const float u = (float)(code & 0xffu) * (2.0f / 255.0f) - 1.0f;
  const float v = (float)(code >> 8) * (2.0f / 255.0f) - 1.0f;
  float3 n = (float3)(u, v, 1.0f - fabs(u) - fabs(v));
  if (n.z < 0.0f) {
    n.x = (1.0f - fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    n.y = (1.0f - fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
  }
  return normalize3(n);
}

float2 compact_uv(const SceneData* sc, uint vertex) {
  const __global CompactInfo* g = sc->compact;
  const __global ushort* q = &sc->quvs[2 * (size_t)vertex];
  return (float2)(g->uv_lo[0] + g->uv_scale[0] * (float)q[0],
                  g->uv_lo[1] + g->uv_scale[1] * (float)q[1]);
}

uint material_of(const SceneData* sc, uint prim) { return sc->material_ids[prim]; }

// The uv at barycentrics (b0, b1, b2) of the triangle's vertices 0, 1, 2.
float2 uv_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const __global uint* idx = &sc->indices[3 * (size_t)prim];
  const float2 a = compact_uv(sc, idx[0]), b = compact_uv(sc, idx[1]), c = compact_uv(sc, idx[2]);
  return (float2)(a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2);
}

// The interpolated (unnormalised) shading normal; the face normal for a mesh without
// normals, as decode_shading.
float3 normal_at(const SceneData* sc, uint prim, float b0, float b1, float b2) {
  const __global uint* idx = &sc->indices[3 * (size_t)prim];
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
