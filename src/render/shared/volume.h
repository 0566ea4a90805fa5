// The volume raycaster, written once for every backend: a ray taken to voxel space,
// clipped to the grid and walked over 16^3 blocks (Amanatides & Woo 1987), blocks (and,
// where the backend has them, 4^3 cells) that nothing visible can lie in skipped,
// samples on the lattice t0 + k dt trilinearly interpolated, looked up in the transfer
// table (transfer.h), shaded by a headlight about the gradient and composited front to
// back with early ray termination. Consecutive blocks share their ends exactly and a
// sample's index is a function of t alone, so the lattice splits between blocks (and
// cells) without a sample lost or taken twice.
//
// The voxels are the backend's: a VolumeGrid with `mr_int n[3]` (voxels per axis) and
// `mr_float3 spacing` (world units), read through `float volume_voxel(const VolumeGrid*,
// mr_int x, mr_int y, mr_int z)` (x fastest). The functions reading voxels are
// MR_GRID_FUNCTIONs: in C++ templates over the grid type (the CPU keeps 8- and 16-bit
// stores), in OpenCL C plain functions over the kernel's VolumeGrid.
#ifndef MULTIRAY_RENDER_SHARED_VOLUME_H
#define MULTIRAY_RENDER_SHARED_VOLUME_H

#ifdef __cplusplus
#include "render/shared/language.h"
#include "render/shared/transfer.h"
#define MR_GRID_FUNCTION      \
  template <class VolumeGrid> \
  inline
#else
#define MR_GRID_FUNCTION
#endif

MR_NAMESPACE_BEGIN

#define MR_VOLUME_BLOCK 16     // voxels per block edge (volume/blocks.h kBlockSize)
#define MR_VOLUME_SKIP_CELL 4  // voxels per skip-cell edge (render/skip_cells.h kSkipCell)

// std::max and std::min (the first argument on ties), as the CPU's code called them.
MR_DEVICE float max_std(float a, float b) { return a < b ? b : a; }
MR_DEVICE float min_std(float a, float b) { return b < a ? b : a; }

// The ray in voxel coordinates (voxel i spans [i, i + 1)); t stays the world ray's.
typedef struct {
  float o[3], d[3];
} VoxelRay;

// The ray's parameter interval [*t0, *t1) inside a grid of n voxels per axis; *t0 >= 0
// (the camera may sit inside); empty when *t0 >= *t1.
MR_DEVICE void voxel_ray_clip(const mr_int n[3], const VoxelRay* r, float* t0, float* t1) {
  *t0 = 0.0f;
  *t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float o = r->o[a], d = r->d[a], na = (float)n[a];
    if (d == 0.0f) {
      if (o < 0.0f || o > na) *t0 = INFINITY;
      continue;
    }
    float ta = (0.0f - o) / d, tb = (na - o) / d;
    if (ta > tb) {
      const float t = ta;
      ta = tb;
      tb = t;
    }
    *t0 = max_std(*t0, ta);
    *t1 = min_std(*t1, tb);
  }
}

// A walk over the cells of `size`^3 voxels (n of them per axis) that a voxel ray crosses.
typedef struct {
  mr_int n[3], cell[3], step[3];
  float next[3], delta[3];
  float t;    // where the next cell starts
  bool done;  // the walk left the grid
} GridWalk;

MR_DEVICE GridWalk grid_walk_start(const mr_int n[3], mr_int size, const VoxelRay* r, float t0) {
  GridWalk w;
  w.t = t0;
  w.done = false;
  for (int a = 0; a < 3; ++a) {
    const float d = r->d[a];
    w.n[a] = n[a];
    w.cell[a] = mr_clamp((mr_int)mr_floor((r->o[a] + d * t0) / (float)size), 0, n[a] - 1);
    w.step[a] = d > 0.0f ? 1 : -1;
    if (d == 0.0f) {
      w.next[a] = w.delta[a] = INFINITY;
      continue;
    }
    const float edge = (float)((w.cell[a] + (d > 0.0f ? 1 : 0)) * size);
    w.next[a] = (edge - r->o[a]) / d;
    w.delta[a] = (float)size / mr_fabs(d);
  }
  return w;
}

// The next cell before t1: its index (x fastest) and its part [*enter, *exit) of the ray;
// false once the walk has reached t1 or left the grid.
MR_DEVICE bool grid_walk_next(GridWalk* w, float t1, mr_ulong* index, float* enter, float* exit) {
  if (w->done || !(w->t < t1)) return false;
  const int a = w->next[0] <= w->next[1] && w->next[0] <= w->next[2] ? 0
                : w->next[1] <= w->next[2]                           ? 1
                                                                     : 2;
  *enter = w->t;
  *exit = min_std(max_std(w->next[a], w->t), t1);
  *index = ((mr_ulong)w->cell[2] * (mr_ulong)w->n[1] + (mr_ulong)w->cell[1]) * (mr_ulong)w->n[0] +
           (mr_ulong)w->cell[0];
  w->t = *exit;
  w->cell[a] += w->step[a];
  if (w->cell[a] < 0 || w->cell[a] >= w->n[a])
    w->done = true;
  else
    w->next[a] += w->delta[a];
  return true;
}

// Trilinear interpolation at voxel coordinates p (voxel centres at i + 0.5), clamped to
// the grid.
MR_GRID_FUNCTION float volume_trilinear(const VolumeGrid* g, mr_float3 p) {
  const mr_int nx = g->n[0], ny = g->n[1], nz = g->n[2];
  const float x = clamp_std(p.x - 0.5f, 0.0f, (float)(nx - 1));
  const float y = clamp_std(p.y - 0.5f, 0.0f, (float)(ny - 1));
  const float z = clamp_std(p.z - 0.5f, 0.0f, (float)(nz - 1));
  const mr_int x0 = mr_min_int((mr_int)x, mr_max_int(nx - 2, 0));
  const mr_int y0 = mr_min_int((mr_int)y, mr_max_int(ny - 2, 0));
  const mr_int z0 = mr_min_int((mr_int)z, mr_max_int(nz - 2, 0));
  const mr_int x1 = mr_min_int(x0 + 1, nx - 1), y1 = mr_min_int(y0 + 1, ny - 1),
               z1 = mr_min_int(z0 + 1, nz - 1);
  const float fx = x - (float)x0, fy = y - (float)y0, fz = z - (float)z0;
  const float v000 = volume_voxel(g, x0, y0, z0), v010 = volume_voxel(g, x0, y1, z0);
  const float v001 = volume_voxel(g, x0, y0, z1), v011 = volume_voxel(g, x0, y1, z1);
  const float r00 = v000 + (volume_voxel(g, x1, y0, z0) - v000) * fx;
  const float r10 = v010 + (volume_voxel(g, x1, y1, z0) - v010) * fx;
  const float r01 = v001 + (volume_voxel(g, x1, y0, z1) - v001) * fx;
  const float r11 = v011 + (volume_voxel(g, x1, y1, z1) - v011) * fx;
  const float a = r00 + (r10 - r00) * fy;
  const float b = r01 + (r11 - r01) * fy;
  return a + (b - a) * fz;
}

// World-space gradient by central differences, one voxel to each side (6 fetches).
MR_GRID_FUNCTION mr_float3 volume_gradient(const VolumeGrid* g, mr_float3 p) {
  const mr_float3 dx = MR_FLOAT3(1.0f, 0.0f, 0.0f), dy = MR_FLOAT3(0.0f, 1.0f, 0.0f),
                  dz = MR_FLOAT3(0.0f, 0.0f, 1.0f);
  return MR_FLOAT3(
      (volume_trilinear(g, p + dx) - volume_trilinear(g, p - dx)) / (2.0f * g->spacing.x),
      (volume_trilinear(g, p + dy) - volume_trilinear(g, p - dy)) / (2.0f * g->spacing.y),
      (volume_trilinear(g, p + dz) - volume_trilinear(g, p - dz)) / (2.0f * g->spacing.z));
}

// What one frame shows and skips: the transfer table (rgb, log(1 - alpha) per entry),
// the step, and per block (and per skip cell, where the backend has them; null otherwise)
// the largest opacity the table can give there.
typedef struct {
  const MR_GLOBAL mr_float4* table;
  mr_uint last;  // table entries - 1
  float table_lo, to_index;
  float dt;                // world units
  float ratio;             // step / reference step (opacity correction)
  float ert;               // early ray termination at this opacity
  float ambient, diffuse;  // the headlight
  bool skip_empty;
  const MR_GLOBAL float* block_opacity;
  const MR_GLOBAL float* cell_opacity;
  mr_int blocks[3], cells[3];
} VolumeShading;

// The composite so far, front to back.
typedef struct {
  mr_float3 colour;
  float alpha;
  mr_uint steps;
  bool opaque;  // early ray termination reached
} VolumeAccum;

// The first lattice index at or after t.
MR_DEVICE mr_long volume_first_index(float t, float t0, float dt) {
  const float d = t - t0;
  return (mr_long)mr_ceil((d < 0.0f ? 0.0f : d) / dt);
}

// The samples of [ta, tb) of the lattice t0 + k dt on voxel ray `r`; `view_dir` is the
// world ray's unit direction (the headlight).
MR_GRID_FUNCTION void volume_march(const VolumeGrid* g, const VolumeShading* s, const VoxelRay* r,
                                   mr_float3 view_dir, float t0, float ta, float tb,
                                   VolumeAccum* acc) {
  const mr_float3 org = MR_FLOAT3(r->o[0], r->o[1], r->o[2]);
  const mr_float3 dir = MR_FLOAT3(r->d[0], r->d[1], r->d[2]);
  const mr_long end = volume_first_index(tb, t0, s->dt);
  for (mr_long k = volume_first_index(ta, t0, s->dt); k < end; ++k) {
    const mr_float3 p = org + dir * (t0 + (float)k * s->dt);
    ++acc->steps;
    const TfSample tf = tf_lookup(
        s->table, s->last, tf_position(volume_trilinear(g, p), s->table_lo, s->to_index, s->last));
    if (tf.log_t == 0.0f) continue;  // fully transparent: no gradient, no change
    const float a = tf_opacity(tf.log_t, s->ratio);
    mr_float3 c = tf.colour;
    const mr_float3 grad = volume_gradient(g, p);
    const float glen = mr_sqrt(dot3(grad, grad));
    if (glen > 0.0f) c = c * (s->ambient + s->diffuse * mr_fabs(dot3(grad, view_dir)) / glen);
    acc->colour = acc->colour + c * ((1.0f - acc->alpha) * a);
    acc->alpha += (1.0f - acc->alpha) * a;
    if (acc->alpha >= s->ert) {
      acc->opaque = true;
      return;
    }
  }
}

// The samples of block part [ta, tb): inside a block that is not empty, its skip cells,
// the empty ones passed over. A walk cut short by rounding at the grid's faces leaves the
// rest unskipped.
MR_GRID_FUNCTION void volume_march_cells(const VolumeGrid* g, const VolumeShading* s,
                                         const VoxelRay* r, mr_float3 view_dir, float t0, float ta,
                                         float tb, VolumeAccum* acc) {
  GridWalk w = grid_walk_start(s->cells, MR_VOLUME_SKIP_CELL, r, ta);
  mr_ulong cell;
  float ca, cb;
  while (grid_walk_next(&w, tb, &cell, &ca, &cb)) {
    if (s->cell_opacity[cell] == 0.0f) continue;
    volume_march(g, s, r, view_dir, t0, ca, cb, acc);
    if (acc->opaque) return;
  }
  if (w.t < tb) volume_march(g, s, r, view_dir, t0, w.t, tb, acc);
}

// The composited radiance along the world ray (eye, unit dir) through a volume whose
// corner is `lower`, over `background`.
MR_GRID_FUNCTION mr_float3 volume_cast(const VolumeGrid* g, const VolumeShading* s,
                                       mr_float3 lower, mr_float3 background, mr_float3 eye,
                                       mr_float3 dir, mr_uint* steps) {
  VoxelRay r;
  r.o[0] = (eye.x - lower.x) / g->spacing.x;
  r.o[1] = (eye.y - lower.y) / g->spacing.y;
  r.o[2] = (eye.z - lower.z) / g->spacing.z;
  r.d[0] = dir.x / g->spacing.x;
  r.d[1] = dir.y / g->spacing.y;
  r.d[2] = dir.z / g->spacing.z;
  float t0, t1;
  voxel_ray_clip(g->n, &r, &t0, &t1);
  VolumeAccum acc;
  acc.colour = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  acc.alpha = 0.0f;
  acc.steps = 0u;
  acc.opaque = false;
  if (t0 < t1) {
    const bool fine = s->skip_empty && s->cell_opacity != 0;
    GridWalk w = grid_walk_start(s->blocks, MR_VOLUME_BLOCK, &r, t0);
    mr_ulong block;
    float ta, tb;
    while (!acc.opaque && grid_walk_next(&w, t1, &block, &ta, &tb)) {
      if (s->skip_empty && s->block_opacity[block] == 0.0f) continue;
      if (fine)
        volume_march_cells(g, s, &r, dir, t0, ta, tb, &acc);
      else
        volume_march(g, s, &r, dir, t0, ta, tb, &acc);
    }
  }
  *steps += acc.steps;
  return acc.colour + background * (1.0f - acc.alpha);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_VOLUME_H
