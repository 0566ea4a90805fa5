// The compact mesh (render/compact_scene.h: Seo et al.'s quantized positions, octahedral
// normals, shifted uv codes, bit-packed faces and material ids) read through one view of
// its arrays, for every backend: the CPU's shading decodes a triangle with it
// (render/shading_data.cpp, decode_shading), the OpenCL kernels their shading and
// triangle corners (kernels/shading.cl, traverse_compact.cl).
#ifndef MULTIRAY_RENDER_SHARED_COMPACT_MESH_H
#define MULTIRAY_RENDER_SHARED_COMPACT_MESH_H

#ifdef __cplusplus
#include "render/shared/bvh_records.h"
#include "render/shared/compact.h"
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  const MR_GLOBAL CompactInfo* info;      // the scalars: grid, uv coding, bit widths
  const MR_GLOBAL mr_ushort* qpos;        // 3 a vertex (QuantizedPosition)
  const MR_GLOBAL mr_ushort* cells;       // the grid's cell-index table, 3 a geometry cell
  const MR_GLOBAL mr_uint* indices;       // 3 vertex indices a triangle, bit-packed
  const MR_GLOBAL mr_ushort* normals;     // a code a vertex (read only when has_normals)
  const MR_GLOBAL mr_ushort* uvs;         // 2 codes a vertex (read only when has_uvs)
  const MR_GLOBAL mr_uint* uv_shifts;     // an entry a triangle, bit-packed
  const MR_GLOBAL mr_uint* material_ids;  // bit-packed
} CompactMeshView;

// Vertex k of triangle `prim`.
MR_DEVICE mr_uint compact_vertex(const CompactMeshView* m, mr_uint prim, int k) {
  return compact_read_bits(m->indices, 3u * (mr_ulong)prim + (mr_ulong)k, m->info->widths & 0xffu);
}

MR_DEVICE mr_float3 compact_position(const CompactMeshView* m, mr_uint vertex) {
  const MR_GLOBAL CompactInfo* g = m->info;
  const MR_GLOBAL mr_ushort* q = m->qpos + 3u * (mr_ulong)vertex;
  return compact_decode_position(load3(g->origin), g->cell, g->step, m->cells, q[0],
                                 (mr_uint)q[1] | (mr_uint)q[2] << 16);
}

MR_DEVICE mr_float3 compact_corner(const CompactMeshView* m, mr_uint prim, int k) {
  return compact_position(m, compact_vertex(m, prim, k));
}

MR_DEVICE mr_uint compact_material(const CompactMeshView* m, mr_uint prim) {
  return compact_read_bits(m->material_ids, prim, (m->info->widths >> 8) & 0xffu);
}

// Corner k's uv: the triangle's shifts and the vertex's codes; zero without uvs (their
// array is then a placeholder, never read).
MR_DEVICE mr_float2 compact_uv(const CompactMeshView* m, mr_uint prim, int k) {
  const MR_GLOBAL CompactInfo* g = m->info;
  if (!g->has_uvs) return MR_FLOAT2(0.0f, 0.0f);
  const MR_GLOBAL mr_ushort* q = m->uvs + 2u * (mr_ulong)compact_vertex(m, prim, k);
  const mr_uint bits_u = (g->widths >> 16) & 0xffu, bits_v = g->widths >> 24;
  const mr_uint entry = compact_read_bits(m->uv_shifts, prim, bits_u + bits_v);
  return MR_FLOAT2(compact_decode_uv(compact_uv_shift(entry, bits_u, g->uv_shift_base[0], 0u),
                                     q[0], g->uv_period_log2[0], g->uv_step[0]),
                   compact_decode_uv(compact_uv_shift(entry, bits_u, g->uv_shift_base[1], 1u),
                                     q[1], g->uv_period_log2[1], g->uv_step[1]));
}

// A triangle's corner normals (its face normal for a mesh without normals), uvs and
// material: what render/shading_data.h's TriangleShading holds.
MR_DEVICE void compact_shading(const CompactMeshView* m, mr_uint prim, mr_float3 normal[3],
                               mr_float2 uv[3], mr_uint* material) {
  if (m->info->has_normals) {
    for (int k = 0; k < 3; ++k)
      normal[k] = compact_decode_normal(m->normals[compact_vertex(m, prim, k)]);
  } else {
    const mr_float3 p0 = compact_corner(m, prim, 0);
    const mr_float3 face =
        normalize3(cross3(compact_corner(m, prim, 1) - p0, compact_corner(m, prim, 2) - p0));
    normal[0] = normal[1] = normal[2] = face;
  }
  for (int k = 0; k < 3; ++k) uv[k] = compact_uv(m, prim, k);
  *material = compact_material(m, prim);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_COMPACT_MESH_H
