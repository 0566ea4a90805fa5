// The volume raycaster of render/volume_raycaster.cpp as one OpenCL kernel: one work-item
// per pixel of a rectangle, all of the pixel's samples. Step for step as the CPU: the ray
// through the pixel centre for one sample (jittered by rng_for_path for more), normalised,
// taken to voxel space, clipped to the grid and walked over 16^3 blocks (Amanatides & Woo,
// render/volume_march.h) with consecutive blocks sharing their ends, so the lattice
// t0 + k dt splits between blocks exactly as on the CPU; blocks of opacity 0 are skipped
// when the style says so; sampling is volume_sample.cl.

// std::max and std::min (the first argument on ties), as volume_march.h calls them.
float max_std(float a, float b) { return a < b ? b : a; }
float min_std(float a, float b) { return b < a ? b : a; }

// The ray in voxel coordinates (voxel i spans [i, i + 1)); t stays the world ray's.
typedef struct {
  float o[3], d[3];
} VoxelRay;

// The ray's parameter interval [*t0, *t1) inside the grid; empty when *t0 >= *t1.
void clip_to_grid(const Grid* g, const VoxelRay* r, float* t0, float* t1) {
  *t0 = 0.0f, *t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float o = r->o[a], d = r->d[a], n = (float)g->n[a];
    if (d == 0.0f) {
      if (o < 0.0f || o > n) *t0 = INFINITY;
      continue;
    }
    float ta = (0.0f - o) / d, tb = (n - o) / d;
    if (ta > tb) {
      const float t = ta;
      ta = tb, tb = t;
    }
    *t0 = max_std(*t0, ta), *t1 = min_std(*t1, tb);
  }
}

// Marches the blocks the ray crosses in [t0, t1) in order (walk_blocks), sampling those
// that may be visible; stops at early ray termination.
void walk_blocks(const Grid* g, const Style* s, const int bn[3], const VoxelRay* r,
                 float3 view_dir, float t0, float t1, Accum* acc) {
  const float3 org = (float3)(r->o[0], r->o[1], r->o[2]);
  const float3 dir = (float3)(r->d[0], r->d[1], r->d[2]);
  const float3 p3 = org + dir * t0;
  const float p[3] = {p3.x, p3.y, p3.z};
  int cell[3], step[3];
  float next[3], delta[3];
  for (int a = 0; a < 3; ++a) {
    cell[a] = clamp((int)floor(p[a] / (float)BLOCK_SIZE), 0, bn[a] - 1);
    const float d = r->d[a];
    step[a] = d > 0.0f ? 1 : -1;
    if (d == 0.0f) {
      next[a] = delta[a] = INFINITY;
      continue;
    }
    const float edge = (float)((cell[a] + (d > 0.0f ? 1 : 0)) * BLOCK_SIZE);
    next[a] = (edge - r->o[a]) / d;
    delta[a] = (float)BLOCK_SIZE / fabs(d);
  }
  float t = t0;
  while (t < t1) {
    const int a = next[0] <= next[1] && next[0] <= next[2] ? 0 : next[1] <= next[2] ? 1 : 2;
    const float exit = min_std(max_std(next[a], t), t1);
    const ulong block =
        ((ulong)cell[2] * (ulong)bn[1] + (ulong)cell[1]) * (ulong)bn[0] + (ulong)cell[0];
    if (!(s->skip_empty && s->max_opacity[block] == 0.0f) &&
        !march(g, s, org, dir, view_dir, t0, first_index(t, t0, s->dt),
               first_index(exit, t0, s->dt), acc))
      return;
    t = exit;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= bn[a]) return;
    next[a] += delta[a];
  }
}

// One ray's composited radiance (VolumeRaycaster::cast); adds its samples to *steps.
float3 cast(const Grid* g, const Style* s, const int bn[3], float3 lower, float3 background,
            float3 eye, float3 view_dir, uint* steps) {
  VoxelRay r;
  const float3 o = (eye - lower) / g->spacing, d = view_dir / g->spacing;
  r.o[0] = o.x, r.o[1] = o.y, r.o[2] = o.z;
  r.d[0] = d.x, r.d[1] = d.y, r.d[2] = d.z;
  float t0, t1;
  clip_to_grid(g, &r, &t0, &t1);
  Accum acc = {(float3)(0.0f), 0.0f, 0u};
  if (t0 < t1) walk_blocks(g, s, bn, &r, view_dir, t0, t1, &acc);
  *steps += acc.steps;
  return acc.colour + background * (1.0f - acc.alpha);
}

// Renders the rects of *batch (batch_rects.h: work-item i finds its rect and pixel (x, y)
// there) of a view `width` pixels wide (every scalar is in *params, volume_params.h, which
// also lists the arguments); work-item i does its pixel with `spp` samples, or spp_map[i]
// when use_spp_map, and writes its mean radiance to radiance[i] (w unused; 0 for a pixel
// without samples) and its volume samples to steps[i].
// Built with -DMR_GROUP_ITEMS and -DMR_LAUNCH_ITEMS as the path tracer.
#define REQD_GROUP_SIZE __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1)))
__kernel REQD_GROUP_SIZE void render_volume(MR_VOLUME_ARGS(MR_ARG_PARAM, MR_ARG_COMMA)) {
  const VolumeParams p = *params;
  const uint i = (uint)get_global_id(0);
  uint first;
  const int k = batch_rect_of(batch, i, &first);
  if (k < 0) return;
  const int4 rect = batch->rects[k];
  const Grid g = {values, {p.dims.x, p.dims.y, p.dims.z}, p.spacing.xyz};
  // clang-format off
  const Style s = {table, block_opacity, p.table_size, p.table_lo, p.table_to_index, p.dt,
                   p.step_ratio, p.ert_threshold, p.blocks.w != 0};
  // clang-format on
  const int bn[3] = {p.blocks.x, p.blocks.y, p.blocks.z};
  const int x = rect.x + (int)((i - first) % (uint)rect.z);
  const int y = rect.y + (int)((i - first) / (uint)rect.z);
  const uint pixel = (uint)y * p.width + (uint)x;
  const int samples = p.use_spp_map ? (int)spp_map[i] : p.spp;
  float3 sum = (float3)(0.0f);
  uint count = 0;
  for (int k = 0; k < samples; ++k) {
    float jx = 0.5f, jy = 0.5f;  // one sample: the pixel centre
    if (samples > 1) {
      RngState rng = rng_for_path(pixel, p.first_sample + (uint)k, p.frame, p.view, p.seed);
      jx = rng_next(&rng), jy = rng_next(&rng);
    }
    // PinholeCamera::ray normalises, and the CPU raycaster normalises once more.
    const float3 dir = normalize3(camera_dir(&p.camera, (float)x + jx, (float)y + jy));
    sum += cast(&g, &s, bn, p.lower.xyz, p.background.xyz, p.camera.eye.xyz, dir, &count);
  }
  radiance[i] = samples > 0 ? (float4)(sum * (1.0f / (float)samples), 0.0f) : (float4)(0.0f);
  steps[i] = count;
}
