// Marching a ray through a volume's grid and its 16^3-voxel blocks: the pieces the
// raycaster (volume_raycaster.cpp) and the cost prediction's pre-pass (volume_prepass.cpp)
// share, so both see exactly the same blocks at the same ray parameters.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "render/accel.h"
#include "volume/blocks.h"
#include "volume/volume.h"

namespace multiray {

// The ray in voxel coordinates (voxel i spans [i, i+1) on each axis); the parameter t is
// the world ray's, so distances and steps stay in world units.
struct VoxelRay {
  Vec3 org, dir;
};

inline VoxelRay to_voxels(const Volume& v, const Ray& r) {
  const Vec3 lo = v.lower();
  return {Vec3((r.org.x - lo.x) / v.spacing.x, (r.org.y - lo.y) / v.spacing.y,
               (r.org.z - lo.z) / v.spacing.z),
          Vec3(r.dir.x / v.spacing.x, r.dir.y / v.spacing.y, r.dir.z / v.spacing.z)};
}

// The ray's parameter interval inside [0, n) on every axis; t0 >= 0 (the camera may sit
// inside the volume). Empty (t0 >= t1) when it misses.
inline void clip_to_grid(const Volume& v, const VoxelRay& r, float& t0, float& t1) {
  const float n[3] = {float(v.nx), float(v.ny), float(v.nz)};
  t0 = 0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float o = r.org[a], d = r.dir[a];
    if (d == 0) {
      if (o < 0 || o > n[a]) t0 = INFINITY;
      continue;
    }
    float ta = (0 - o) / d, tb = (n[a] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
}

// Walks the cells of `kCell`^3 voxels (n[0] x n[1] x n[2] of them) a voxel ray crosses
// between t0 and t1 in order (Amanatides & Woo 1987), calling visit(cell index, t_enter,
// t_exit); consecutive intervals share their ends exactly, so a function of t alone
// partitions the ray's samples between cells. Stops when visit returns false, or when the
// walk leaves the grid; returns the t it reached (t1 unless it stopped early).
template <int kCell, class Visit>
float walk_grid(const int n[3], const VoxelRay& r, float t0, float t1, Visit visit) {
  int cell[3], step[3];
  float next[3], delta[3];
  const Vec3 p = r.org + r.dir * t0;
  for (int a = 0; a < 3; ++a) {
    cell[a] = std::clamp(int(std::floor(p[a] / kCell)), 0, n[a] - 1);
    const float d = r.dir[a];
    step[a] = d > 0 ? 1 : -1;
    if (d == 0) {
      next[a] = delta[a] = INFINITY;
      continue;
    }
    const float edge = float((cell[a] + (d > 0 ? 1 : 0)) * kCell);
    next[a] = (edge - r.org[a]) / d;
    delta[a] = float(kCell) / std::abs(d);
  }
  float t = t0;
  while (t < t1) {
    const int a = next[0] <= next[1] && next[0] <= next[2] ? 0 : next[1] <= next[2] ? 1 : 2;
    const float exit = std::min(std::max(next[a], t), t1);
    const size_t index =
        (size_t(cell[2]) * size_t(n[1]) + size_t(cell[1])) * size_t(n[0]) + size_t(cell[0]);
    if (!visit(index, t, exit)) return exit;
    t = exit;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= n[a]) return t;
    next[a] += delta[a];
  }
  return t;
}

// walk_grid over the 16^3 blocks of Bruder et al. (volume/blocks.h).
template <class Visit>
void walk_blocks(const VolumeBlocks& b, const VoxelRay& r, float t0, float t1, Visit visit) {
  const int n[3] = {b.bx, b.by, b.bz};
  walk_grid<kBlockSize>(n, r, t0, t1, visit);
}

}  // namespace multiray
