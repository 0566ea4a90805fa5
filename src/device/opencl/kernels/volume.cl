// The volume raycaster's entry point: render/shared/volume.h (written once for every
// backend) over this backend's voxels (floats, x fastest), one work-item per pixel of a
// rectangle, all of the pixel's samples: the ray through the pixel centre for one sample
// (jittered by rng_for_path for more), normalised as the CPU's camera and raycaster do.

// Renders the rects of *batch (batch_rects.h: work-item i finds its rect and pixel (x, y)
// there) of a view `width` pixels wide (every scalar is in *params, volume_params.h, which
// also lists the arguments); work-item i does its pixel with `spp` samples, or spp_map[i]
// when use_spp_map, and writes its mean radiance to radiance[i] (w unused; 0 for a pixel
// without samples) and its volume samples to steps[i]. Built with -DMR_GROUP_ITEMS.
__kernel __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1))) void render_volume(
    MR_VOLUME_ARGS(MR_ARG_PARAM, MR_ARG_COMMA)) {
  const VolumeParams p = *params;
  const uint i = (uint)get_global_id(0);
  uint first;
  const int k = batch_rect_of(batch, i, &first);
  if (k < 0) return;
  const int4 rect = batch->rects[k];
  const VolumeGrid g = {values, {p.dims.x, p.dims.y, p.dims.z}, p.spacing.xyz};
  const VolumeShading s = {table,        p.table_size - 1u, p.table_lo,    p.table_to_index,
                           p.dt,         p.step_ratio,      p.ert_threshold, 0.3f,
                           0.7f,         p.blocks.w != 0,   block_opacity, 0,
                           {p.blocks.x, p.blocks.y, p.blocks.z}, {0, 0, 0}};
  const int x = rect.x + (int)((i - first) % (uint)rect.z);
  const int y = rect.y + (int)((i - first) / (uint)rect.z);
  const uint pixel = (uint)y * p.width + (uint)x;
  const int samples = p.use_spp_map ? (int)spp_map[i] : p.spp;
  float3 sum = (float3)(0.0f);
  uint count = 0;
  for (int n = 0; n < samples; ++n) {
    float jx = 0.5f, jy = 0.5f;  // one sample: the pixel centre
    if (samples > 1) {
      RngState rng = rng_for_path(pixel, p.first_sample + (uint)n, p.frame, p.view, p.seed);
      jx = rng_next(&rng), jy = rng_next(&rng);
    }
    const float3 dir = normalize3(camera_dir(&p.camera, (float)x + jx, (float)y + jy));
    sum += volume_cast(&g, &s, p.lower.xyz, p.background.xyz, p.camera.eye.xyz, dir, &count);
  }
  radiance[i] = samples > 0 ? (float4)(sum * (1.0f / (float)samples), 0.0f) : (float4)(0.0f);
  steps[i] = count;
}
