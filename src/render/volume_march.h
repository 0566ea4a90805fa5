// Marching a ray through a volume's grid and its 16^3-voxel blocks, for the CPU's callers
// that walk blocks themselves (the cost prediction's pre-pass, volume_prepass.cpp; the
// non-empty span of a ray): C++ faces of render/shared/volume.h, whose walk the
// raycaster itself uses on every backend, so all see exactly the same blocks at the same
// ray parameters.
#pragma once

#include <cstddef>

#include "render/accel.h"
#include "render/shared/volume.h"
#include "volume/blocks.h"
#include "volume/volume.h"

namespace multiray {

// The ray in voxel coordinates (voxel i spans [i, i+1) on each axis); the parameter t is
// the world ray's, so distances and steps stay in world units.
inline VoxelRay to_voxels(const Volume& v, const Ray& r) {
  const Vec3 lo = v.lower();
  return VoxelRay{{(r.org.x - lo.x) / v.spacing.x, (r.org.y - lo.y) / v.spacing.y,
                   (r.org.z - lo.z) / v.spacing.z},
                  {r.dir.x / v.spacing.x, r.dir.y / v.spacing.y, r.dir.z / v.spacing.z}};
}

// The ray's parameter interval inside [0, n) on every axis; t0 >= 0 (the camera may sit
// inside the volume). Empty (t0 >= t1) when it misses.
inline void clip_to_grid(const Volume& v, const VoxelRay& r, float& t0, float& t1) {
  const int n[3] = {v.nx, v.ny, v.nz};
  voxel_ray_clip(n, &r, &t0, &t1);
}

// Walks the cells of `kCell`^3 voxels (n[0] x n[1] x n[2] of them) a voxel ray crosses
// between t0 and t1 in order, calling visit(cell index, t_enter, t_exit); consecutive
// intervals share their ends exactly, so a function of t alone partitions the ray's
// samples between cells. Stops when visit returns false, or when the walk leaves the
// grid; returns the t it reached (t1 unless it stopped early).
template <int kCell, class Visit>
float walk_grid(const int n[3], const VoxelRay& r, float t0, float t1, Visit visit) {
  GridWalk w = grid_walk_start(n, kCell, &r, t0);
  mr_ulong index;
  float ta, tb;
  while (grid_walk_next(&w, t1, &index, &ta, &tb))
    if (!visit(size_t(index), ta, tb)) return tb;
  return w.t;
}

// walk_grid over the 16^3 blocks of Bruder et al. (volume/blocks.h).
template <class Visit>
void walk_blocks(const VolumeBlocks& b, const VoxelRay& r, float t0, float t1, Visit visit) {
  static_assert(kBlockSize == MR_VOLUME_BLOCK);
  const int n[3] = {b.bx, b.by, b.bz};
  walk_grid<kBlockSize>(n, r, t0, t1, visit);
}

}  // namespace multiray
