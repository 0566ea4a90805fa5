// The voxels as this backend holds them (floats, x fastest): the VolumeGrid that
// render/shared/volume.h reads through volume_voxel.

typedef struct {
  const __global float* values;
  int n[3];
  float3 spacing;
} VolumeGrid;

float volume_voxel(const VolumeGrid* g, int x, int y, int z) {
  return g->values[((ulong)z * (ulong)g->n[1] + (ulong)y) * (ulong)g->n[0] + (ulong)x];
}
