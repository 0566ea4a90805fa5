// Sampling a volume as render/volume_raycaster.cpp does: the trilinear fetch clamped to the
// grid, the table of (rgb, log(1 - alpha)) with linear interpolation and opacity
// correction (render/shared/transfer.h), the central-difference gradient, headlight
// shading and front-to-back compositing with early ray termination, in the CPU's order of
// operations (contraction off, render/shared/language.h). The walk that calls it is in
// volume.cl.

#define BLOCK_SIZE 16  // kBlockSize
#define AMBIENT 0.3f   // kAmbient
#define DIFFUSE 0.7f   // kDiffuse

typedef struct {
  const __global float* values;  // x fastest, then y, z
  int n[3];                      // voxels per axis
  float3 spacing;
} Grid;

float voxel(const Grid* g, int x, int y, int z) {
  return g->values[((ulong)z * (ulong)g->n[1] + (ulong)y) * (ulong)g->n[0] + (ulong)x];
}

// Trilinear interpolation at voxel coordinates p (voxel centres at i + 0.5), clamped to
// the grid (render/volume_raycaster.cpp: trilinear).
float trilinear(const Grid* g, float3 p) {
  const int nx = g->n[0], ny = g->n[1], nz = g->n[2];
  const float x = clamp_std(p.x - 0.5f, 0.0f, (float)(nx - 1));
  const float y = clamp_std(p.y - 0.5f, 0.0f, (float)(ny - 1));
  const float z = clamp_std(p.z - 0.5f, 0.0f, (float)(nz - 1));
  const int x0 = min((int)x, max(nx - 2, 0)), y0 = min((int)y, max(ny - 2, 0)),
            z0 = min((int)z, max(nz - 2, 0));
  const int x1 = min(x0 + 1, nx - 1), y1 = min(y0 + 1, ny - 1), z1 = min(z0 + 1, nz - 1);
  const float fx = x - (float)x0, fy = y - (float)y0, fz = z - (float)z0;
  const float r00 = voxel(g, x0, y0, z0) + (voxel(g, x1, y0, z0) - voxel(g, x0, y0, z0)) * fx;
  const float r10 = voxel(g, x0, y1, z0) + (voxel(g, x1, y1, z0) - voxel(g, x0, y1, z0)) * fx;
  const float r01 = voxel(g, x0, y0, z1) + (voxel(g, x1, y0, z1) - voxel(g, x0, y0, z1)) * fx;
  const float r11 = voxel(g, x0, y1, z1) + (voxel(g, x1, y1, z1) - voxel(g, x0, y1, z1)) * fx;
  const float a = r00 + (r10 - r00) * fy;
  const float b = r01 + (r11 - r01) * fy;
  return a + (b - a) * fz;
}

// World-space gradient by central differences, one voxel to each side (6 fetches).
float3 gradient(const Grid* g, float3 p) {
  const float3 dx = (float3)(1.0f, 0.0f, 0.0f), dy = (float3)(0.0f, 1.0f, 0.0f),
               dz = (float3)(0.0f, 0.0f, 1.0f);
  return (float3)((trilinear(g, p + dx) - trilinear(g, p - dx)) / (2.0f * g->spacing.x),
                  (trilinear(g, p + dy) - trilinear(g, p - dy)) / (2.0f * g->spacing.y),
                  (trilinear(g, p + dz) - trilinear(g, p - dz)) / (2.0f * g->spacing.z));
}

// What one frame shows: the table, the block opacities and the step (VolumeStyle).
typedef struct {
  const __global float4* table;       // rgb, log(1 - alpha) per entry
  const __global float* max_opacity;  // per block
  uint table_size;
  float table_lo, to_index, dt, ratio, ert;
  bool skip_empty;
} Style;

// The composite so far, front to back.
typedef struct {
  float3 colour;
  float alpha;
  uint steps;
} Accum;

// The samples k in [first, end) of the lattice t0 + k dt on the voxel ray (org, dir);
// `view_dir` is the world ray's unit direction for the headlight. Returns false once the
// opacity reaches the ERT threshold.
bool march(const Grid* g, const Style* s, float3 org, float3 dir, float3 view_dir, float t0,
           long first, long end, Accum* acc) {
  const uint last = s->table_size - 1;
  for (long k = first; k < end; ++k) {
    const float3 p = org + dir * (t0 + (float)k * s->dt);
    ++acc->steps;
    const float value = trilinear(g, p);
    const TfSample tf =
        tf_lookup(s->table, last, tf_position(value, s->table_lo, s->to_index, last));
    if (tf.log_t == 0.0f) continue;  // fully transparent: no gradient, no change
    const float a = tf_opacity(tf.log_t, s->ratio);
    float3 c = tf.colour;
    const float3 grad = gradient(g, p);
    const float glen = sqrt(dot3(grad, grad));
    if (glen > 0.0f) c = c * (AMBIENT + DIFFUSE * fabs(dot3(grad, view_dir)) / glen);
    acc->colour += c * ((1.0f - acc->alpha) * a);
    acc->alpha += (1.0f - acc->alpha) * a;
    if (acc->alpha >= s->ert) return false;
  }
  return true;
}

// The first lattice index at or after t (a function of t alone: see walk_blocks).
long first_index(float t, float t0, float dt) {
  const float d = t - t0;
  return (long)ceil((d < 0.0f ? 0.0f : d) / dt);
}
