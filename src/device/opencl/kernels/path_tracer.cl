// The path tracer of render/path_tracer.cpp as one OpenCL kernel: one work-item per pixel
// of a rectangle, all of the pixel's samples, paths traced depth-first. Each bounce makes
// the same decisions and draws the same sample values from the same dimensions of
// render/shared/sobol.h as PathTracer::step: one 2D value for the pixel jitter; per bounce
// a block of 5 dimensions: for next-event estimation, when the surface is not a dielectric
// and there is a light to sample (the environment, unless RenderSettings::sample_environment
// is off, or an emissive triangle), one value choosing between them with probability p_env
// and a 2D value placing the sample; a 1D and a 2D value for the BSDF sample; one value
// for Russian roulette from `rr_start` on. So the image matches the CPU's statistically
// and is exactly the same on every device of one type, whatever the split.

// Next-event estimation from a vertex (PathTracer::sample_light): one sample of either the
// environment or an emissive triangle; returns the unoccluded contribution (0 if none).
float3 sample_direct(const SceneData* sc, const BsdfParams* bsdf, const Frame* frame, float3 wo,
                     float3 p, float3 ng, float3 beta, SampleStream* u, uint* rays) {
  const float p_env = sc->p_env;
  float ul = sample_1d(u);
  const float2 u12 = sample_2d(u);
  const float u1 = u12.x, u2 = u12.y;
  Ray shadow;
  shadow.org = p + ng * sc->eps;
  shadow.tmin = 0.0f;
  float3 contribution;
  if (ul < p_env) {
    const EnvSample es = sky_sample(sc, ng, ul / p_env, u1, u2);
    if (!(es.pdf > 0.0f) || dot3(es.dir, ng) <= 0.0f) return (float3)(0.0f);
    const float3 wi = to_local(frame, es.dir);
    const float3 f = bsdf_eval(bsdf, wo, wi);
    if (!(max3(f) > 0.0f)) return (float3)(0.0f);
    const float pdf_light = p_env * es.pdf;
    shadow.dir = es.dir;
    shadow.tmax = INFINITY;
    contribution =
        beta * f * es.radiance * (power_heuristic(pdf_light, bsdf_pdf(bsdf, wo, wi)) / pdf_light);
  } else {
    ul = (ul - p_env) / (1.0f - p_env);  // exactly ul when there is no environment
    const LightSample ls = sample_light(sc, ul, u1, u2);
    const float3 to_light = ls.point - p;
    const float dist2 = dot3(to_light, to_light), dist = sqrt(dist2);
    const float3 wi_world = to_light * (1.0f / dist);
    const float cos_l = -dot3(ls.normal, wi_world);
    if (!(cos_l > 0.0f) || dot3(wi_world, ng) <= 0.0f) return (float3)(0.0f);
    const float3 wi = to_local(frame, wi_world);
    const float3 f = bsdf_eval(bsdf, wo, wi);
    if (!(max3(f) > 0.0f)) return (float3)(0.0f);
    const float pdf_light = (1.0f - p_env) * ls.pdf_area * dist2 / cos_l;
    shadow.dir = wi_world;
    shadow.tmax = dist * (1.0f - 1e-4f) - sc->eps;
    contribution =
        beta * f * ls.radiance * (power_heuristic(pdf_light, bsdf_pdf(bsdf, wo, wi)) / pdf_light);
  }
  ++*rays;
  return occluded(sc, &shadow) ? (float3)(0.0f) : contribution;
}

// One camera path; returns its radiance and adds the rays it traced to *rays.
float3 trace_path(const SceneData* sc, Ray ray, SampleStream* u, int max_bounces, int rr_start,
                  uint* rays) {
  float3 L = (float3)(0.0f), beta = (float3)(1.0f);
  float prev_pdf = 0.0f;
  float3 prev_normal = (float3)(0.0f);  // geometric normal at the last vertex
  bool prev_specular = true;            // the camera ray sees emission directly
  const bool lights_on = sc->p_env > 0.0f || sc->light_count > 0;
  for (int depth = 0;;) {
    Hit hit;
    ++*rays;
    if (!intersect_closest(sc, &ray, &hit)) {
      // PathTracer::escape: weighted against environment sampling at the last vertex.
      const float3 le = sky_radiance(sc, ray.dir);
      float w = 1.0f;
      if (!prev_specular && sc->p_env > 0.0f) {
        const float pdf_env = sc->p_env * sky_pdf(sc, ray.dir, prev_normal);
        w = power_heuristic(prev_pdf, pdf_env);
      }
      return L + beta * le * w;
    }
    // Shading point, as shade_point() on the CPU.
    const float w = 1.0f - hit.u - hit.v;
    const float3 p = ray.org + ray.dir * hit.t;
    float3 ng = normalize3(hit.ng);
    const float3 n = normal_at(sc, hit.prim, w, hit.u, hit.v);
    float3 ns = dot3(n, n) > 0.0f ? normalize3(n) : ng;
    if (dot3(ns, ng) < 0.0f) ns = -ns;
    const float2 uv = uv_at(sc, hit.prim, w, hit.u, hit.v);
    const __global Material* mat = &sc->materials[material_of(sc, hit.prim)];
    const float3 wo_world = -ray.dir;
    const bool front = dot3(ng, wo_world) > 0.0f;

    if (front && mat->emissive) {
      const float3 le = emission_at(sc, mat, uv);
      if (prev_specular) {
        L += beta * le;
      } else {
        const float cos_l = dot3(ng, wo_world);
        const float pdf_light = (1.0f - sc->p_env) * sc->light_pdf_by_prim[hit.prim] *
                                hit.t * hit.t / cos_l;
        L += beta * le * power_heuristic(prev_pdf, pdf_light);
      }
    }
    if (depth >= max_bounces) return L;

    const SurfacePoint sp = surface_at(sc, mat, uv, ns, ng, hit.prim);
    ns = sp.ns;
    const BsdfParams bsdf =
        bsdf_params(sp.base_color, sp.metallic, sp.roughness, mat->ior, mat->dielectric != 0);
    const bool opaque = !bsdf.dielectric;
    // Opaque surfaces are two-sided; dielectrics keep their outward normal.
    if (opaque && !front) ng = -ng, ns = -ns;
    Frame frame = frame_from_normal(ns);
    float3 wo = to_local(&frame, wo_world);
    if (opaque && wo.z <= 0.0f) {
      frame = frame_from_normal(ng);
      wo = to_local(&frame, wo_world);
    }
    sample_stream_at_bounce(u, depth);
    if (opaque && lights_on) L += sample_direct(sc, &bsdf, &frame, wo, p, ng, beta, u, rays);

    // Continue by sampling the BSDF (the bounce's dimensions 2 to 3).
    sample_stream_at_bounce(u, depth);
    u->dim += MR_SOBOL_BSDF_OFFSET;
    BsdfSample bs;
    float u_lobe = 0.0f;  // drawn only when there is a lobe to choose (its dimension kept)
    if (bsdf_chooses_lobe(&bsdf))
      u_lobe = sample_1d(u);
    else
      ++u->dim;
    const float2 u12 = sample_2d(u);
    if (!bsdf_sample(&bsdf, wo, u_lobe, u12.x, u12.y, &bs)) return L;
    const float3 wi_world = to_world(&frame, bs.wi);
    const float side = dot3(wi_world, ng);
    if (opaque && side <= 0.0f) return L;  // shading normal leak
    beta *= bs.weight;
    prev_pdf = bs.pdf;
    prev_specular = bs.specular;
    prev_normal = ng;
    ray.org = p + ng * (side > 0.0f ? sc->eps : -sc->eps);
    ray.dir = wi_world;
    ray.tmin = 0.0f;
    ray.tmax = INFINITY;
    ++depth;
    if (depth >= rr_start) {
      const float q = rr_survival(max3(beta));
      if (q < 1.0f && sample_1d(u) >= q) return L;
      beta = beta * (1.0f / q);
    }
  }
}

// Renders the rects of *batch (batch_rects.h: work-item i finds its rect and pixel (x, y)
// there) of a view `width` pixels wide (width and every other scalar are in *params, see
// launch_params.h, which also lists the arguments); work-item i does its pixel with `spp`
// samples, or spp_map[i] when use_spp_map (irregular sampling), and writes its mean
// radiance to radiance[i] (w unused; 0 for a pixel without samples) and its ray count to
// rays[i].
// Built with -DMR_GROUP_ITEMS (the work-group size every launch uses) and
// -DMR_LAUNCH_ITEMS (the global size every launch uses, see opencl_device.cpp).
#define REQD_GROUP_SIZE __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1)))
__kernel REQD_GROUP_SIZE void render_rect(MR_RENDER_RECT_ARGS(MR_ARG_PARAM, MR_ARG_COMMA)) {
  const LaunchParams p = *params;
  const uint i = (uint)get_global_id(0);
  uint first;
  const int k = batch_rect_of(batch, i, &first);
  if (k < 0) return;
  const int4 rect = batch->rects[k];
  const SceneData sc = {nodes,         tris,           shading,   materials,        lights,
                        light_cdf,     light_pdf_by_prim, texels, textures,         texel_luts,
                        tangents,      sky,            sky_data,  cnodes,           prims,
                        qpos,          cells,          indices,   qnormals,         quvs,
                        uv_shifts,     material_ids,   compact,   p.light_count,  p.has_tangents != 0, p.cutouts != 0,
                        p.env_choice_eps.x, p.env_choice_eps.w};
  const int x = rect.x + (int)((i - first) % (uint)rect.z);
  const int y = rect.y + (int)((i - first) / (uint)rect.z);
  const uint pixel = (uint)y * p.width + (uint)x;
  float3 sum = (float3)(0.0f);
  uint count = 0;
  const int samples = p.use_spp_map ? (int)spp_map[i] : p.spp;
  for (int s = 0; s < samples; ++s) {
    SampleStream u =
        sample_stream_for_path(pixel, p.first_sample + (uint)s, p.frame, p.view, p.seed);
    const float2 j = sample_2d(&u);
    const float jx = j.x, jy = j.y;
    Ray ray;
    ray.org = p.camera.eye.xyz;
    ray.dir = camera_dir(&p.camera, (float)x + jx, (float)y + jy);
    ray.tmin = 0.0f;
    ray.tmax = INFINITY;
    const float3 L = trace_path(&sc, ray, &u, p.max_bounces, p.rr_start, &count);
    sum += clamp_sample(finite3(L) ? L : (float3)(0.0f), p.sample_clamp);
  }
  radiance[i] = samples > 0 ? (float4)(sum * (1.0f / (float)samples), 0.0f) : (float4)(0.0f);
  rays[i] = count;
}
