// The path tracer's entry point: the integrator of render/shared/path.h (written once for
// every backend), one work-item per pixel of a rectangle, its samples' paths traced one
// after another, each depth-first through the BVH walk (render/shared/bvh_walk.h) over
// this program's tree (traverse.cl or traverse_compact.cl).

// One camera path to its end; returns its radiance and adds the rays it traced to *rays.
// `aov`: the sample's feature buffers to record (render/shared/aov.h), or 0.
float3 trace_path(const SceneData* sc, PathState* p, PathSettings settings, AovSample* aov,
                  uint* rays) {
  while (p->alive) {
    Hit hit, unused;
    ++*rays;
    if (!bvh_walk(sc, &p->ray, false, &hit)) {
      path_escape(sc, p, aov);
      break;
    }
    path_shade(sc, p, &hit, settings, 0, aov);
    if (p->has_shadow) {
      ++*rays;
      path_shadow_done(p, bvh_walk(sc, &p->shadow, true, &unused));
    }
  }
  return p->L;
}

// Renders the rects of *batch (batch_rects.h: work-item i finds its rect and pixel (x, y)
// there) of a view `width` pixels wide (width and every other scalar are in *params, see
// launch_params.h, which also lists the arguments); work-item i does its pixel with `spp`
// samples, or spp_map[i] when use_spp_map (irregular sampling), and writes its mean
// radiance to radiance[i] (w unused; 0 for a pixel without samples) and its ray count to
// rays[i]; with feature_buffers, its feature buffers in packed order (aov.h) to
// features[3i] (albedo, depth), features[3i + 1] (normal, variance) and features[3i + 2]
// (emission, w 0), else nothing there. Built with -DMR_GROUP_ITEMS (the work-group size every launch uses).
__kernel __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1))) void render_rect(
    MR_RENDER_RECT_ARGS(MR_ARG_PARAM, MR_ARG_COMMA)) {
  const LaunchParams p = *params;
  const uint i = (uint)get_global_id(0);
  uint first;
  const int k = batch_rect_of(batch, i, &first);
  if (k < 0) return;
  const int4 rect = batch->rects[k];
  // The map's radiance follows its tables (scene_buffers.h).
  const __global float* sky_map =
      sky_data + sky->pix_pdf + (uint)sky->map_width * (uint)sky->map_height;
  const SceneData sc = {nodes, tris, shading, materials, lights, light_cdf, light_pdf_by_prim,
                        texels, textures, texel_luts, tangents, sky, sky_data, sky_map, cnodes,
                        prims, compact,
                        {compact, qpos, cells, indices, qnormals, quvs, uv_shifts, material_ids},
                        p.light_count, p.has_tangents != 0, p.cutouts != 0,
                        p.env_choice_eps.x, p.env_choice_eps.w};
  const PathSettings settings = {p.max_bounces, p.rr_start};
  const int x = rect.x + (int)((i - first) % (uint)rect.z);
  const int y = rect.y + (int)((i - first) / (uint)rect.z);
  const uint pixel = (uint)y * p.width + (uint)x;
  float3 sum = (float3)(0.0f);
  uint count = 0;
  const int samples = p.use_spp_map ? (int)spp_map[i] : p.spp;
  const bool record = p.feature_buffers != 0u;
  AovPixel px;
  if (record) aov_pixel_init(&px);
  for (int s = 0; s < samples; ++s) {
    PathState path;
    path_init(&path, sample_stream_for_path(pixel, p.first_sample + (uint)s, p.frame, p.view,
                                            p.seed));
    const float2 j = sample_2d(&path.u);
    path.ray = make_ray(p.camera.eye.xyz, camera_dir(&p.camera, (float)x + j.x, (float)y + j.y),
                        INFINITY);
    AovSample aov;
    if (record) aov_init(&aov, path.ray.dir, p.camera.forward.xyz);
    const float3 L = trace_path(&sc, &path, settings, record ? &aov : 0, &count);
    const float3 c = clamp_sample(finite3(L) ? L : (float3)(0.0f), p.sample_clamp);
    sum += c;
    if (record) aov_pixel_add(&px, &aov, L, c, p.sample_clamp);
  }
  radiance[i] = samples > 0 ? (float4)(sum * (1.0f / (float)samples), 0.0f) : (float4)(0.0f);
  rays[i] = count;
  if (record) {
    float v[MR_AOV_FLOATS];
    aov_pixel_result(&px, v);
    features[3 * i] = (float4)(v[0], v[1], v[2], v[6]);
    features[3 * i + 1] = (float4)(v[3], v[4], v[5], v[7]);
    features[3 * i + 2] = (float4)(v[8], v[9], v[10], 0.0f);
  }
}
