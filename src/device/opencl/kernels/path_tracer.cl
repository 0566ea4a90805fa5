// The path tracer of render/path_tracer.cpp as one OpenCL kernel: one work-item per pixel
// of a rectangle, all of the pixel's samples, paths traced depth-first. Each bounce makes
// the same decisions and draws the same random numbers in the same order as
// PathTracer::step (2 for the pixel jitter; per bounce 3 for next-event estimation when
// the surface is not a dielectric and the scene has lights, 3 for the BSDF sample, 1 for
// Russian roulette from `rr_start` on), so the image matches the CPU's statistically and
// is exactly the same on every device of one type, whatever the split.

typedef struct {
  const __global Node* nodes;
  const __global Tri* tris;
  const __global Shading* shading;
  const __global Material* materials;
  const __global Light* lights;
  const __global float* light_cdf;
  const __global float* light_pdf_by_prim;
  const __global uint* texels;
  const __global TexInfo* textures;
  const __global float* srgb_lut;
  uint light_count;
  float3 environment;
  float eps;  // ray-origin offset
} SceneData;

// One camera path; returns its radiance and adds the rays it traced to *rays.
float3 trace_path(const SceneData* sc, Ray ray, Rng* rng, int max_bounces, int rr_start,
                  uint* rays) {
  float3 L = (float3)(0.0f), beta = (float3)(1.0f);
  float prev_pdf = 0.0f;
  bool prev_specular = true;  // the camera ray sees emission directly
  for (int depth = 0;;) {
    Hit hit;
    ++*rays;
    if (!intersect_closest(sc->nodes, sc->tris, &ray, &hit)) {
      L += beta * sc->environment;  // never light-sampled: weight 1
      return L;
    }
    // Shading point, as shade_point() on the CPU.
    const __global Shading* d = &sc->shading[hit.prim];
    const float w = 1.0f - hit.u - hit.v;
    const float3 p = ray.org + ray.dir * hit.t;
    float3 ng = normalize3(hit.ng);
    const float3 n =
        load3(d->normal) * w + load3(d->normal + 3) * hit.u + load3(d->normal + 6) * hit.v;
    float3 ns = dot3(n, n) > 0.0f ? normalize3(n) : ng;
    if (dot3(ns, ng) < 0.0f) ns = -ns;
    const float2 uv = (float2)(d->uv[0] * w + d->uv[2] * hit.u + d->uv[4] * hit.v,
                               d->uv[1] * w + d->uv[3] * hit.u + d->uv[5] * hit.v);
    const __global Material* mat = &sc->materials[d->material];
    const float3 wo_world = -ray.dir;
    const bool front = dot3(ng, wo_world) > 0.0f;

    if (front && mat->emissive) {
      const float3 le = load3(mat->emission);
      if (prev_specular) {
        L += beta * le;
      } else {
        const float cos_l = dot3(ng, wo_world);
        const float pdf_light = sc->light_pdf_by_prim[hit.prim] * hit.t * hit.t / cos_l;
        L += beta * le * power_heuristic(prev_pdf, pdf_light);
      }
    }
    if (depth >= max_bounces) return L;

    Bsdf bsdf;
    bsdf.color = load3(mat->color);
    if (mat->texture >= 0)
      bsdf.color *= sample_texture(&sc->textures[mat->texture], sc->texels, sc->srgb_lut, uv);
    bsdf.metallic = mat->metallic;
    bsdf.alpha = mat->alpha;
    bsdf.ior = mat->ior;
    bsdf.dielectric = mat->dielectric != 0;
    const bool opaque = !bsdf.dielectric;
    // Opaque surfaces are two-sided; dielectrics keep their outward normal.
    if (opaque && !front) ng = -ng, ns = -ns;
    Frame frame = frame_from_normal(ns);
    float3 wo = to_local(&frame, wo_world);
    if (opaque && wo.z <= 0.0f) {
      frame = frame_from_normal(ng);
      wo = to_local(&frame, wo_world);
    }

    // Next-event estimation towards one point on one emissive triangle.
    if (opaque && sc->light_count > 0) {
      const float ul = rng_next(rng), u1 = rng_next(rng), u2 = rng_next(rng);
      const LightSample ls = sample_light(sc->lights, sc->light_cdf, sc->light_count, ul, u1, u2);
      const float3 to_light = ls.point - p;
      const float dist2 = dot3(to_light, to_light), dist = sqrt(dist2);
      const float3 wi_world = to_light * (1.0f / dist);
      const float cos_l = -dot3(ls.normal, wi_world);
      if (cos_l > 0.0f && dot3(wi_world, ng) > 0.0f) {
        const float3 wi = to_local(&frame, wi_world);
        const float3 f = bsdf_eval(&bsdf, wo, wi);
        if (max3(f) > 0.0f) {
          const float pdf_light = ls.pdf_area * dist2 / cos_l;
          Ray shadow;
          shadow.org = p + ng * sc->eps;
          shadow.dir = wi_world;
          shadow.tmin = 0.0f;
          shadow.tmax = dist * (1.0f - 1e-4f) - sc->eps;
          ++*rays;
          if (!occluded(sc->nodes, sc->tris, &shadow))
            L += beta * f * ls.radiance *
                 (power_heuristic(pdf_light, bsdf_pdf(&bsdf, wo, wi)) / pdf_light);
        }
      }
    }

    // Continue by sampling the BSDF.
    BsdfSample bs;
    const float u_lobe = rng_next(rng), u1 = rng_next(rng), u2 = rng_next(rng);
    if (!bsdf_sample(&bsdf, wo, u_lobe, u1, u2, &bs)) return L;
    const float3 wi_world = to_world(&frame, bs.wi);
    const float side = dot3(wi_world, ng);
    if (opaque && side <= 0.0f) return L;  // shading normal leak
    beta *= bs.weight;
    prev_pdf = bs.pdf;
    prev_specular = bs.specular;
    ray.org = p + ng * (side > 0.0f ? sc->eps : -sc->eps);
    ray.dir = wi_world;
    ray.tmin = 0.0f;
    ray.tmax = INFINITY;
    ++depth;
    if (depth >= rr_start) {
      const float q = fmin(max3(beta), 0.95f);
      if (rng_next(rng) >= q) return L;
      beta = beta * (1.0f / q);
    }
  }
}

// Renders pixels [rect.x, rect.x + rect.z) x [rect.y, rect.y + rect.w) of a view `width`
// pixels wide (rect, width and every other scalar are in *params, see launch_params.h,
// which also lists the arguments); work-item i does pixel (rect.x + i % rect.z,
// rect.y + i / rect.z) with `spp` samples, or spp_map[i] when use_spp_map (irregular
// sampling), and writes its mean radiance to radiance[i] (w unused; 0 for a pixel without
// samples) and its ray count to rays[i].
// Built with -DMR_GROUP_ITEMS (the work-group size every launch uses) and
// -DMR_LAUNCH_ITEMS (the global size every launch uses, see opencl_device.cpp).
#define REQD_GROUP_SIZE __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1)))
__kernel REQD_GROUP_SIZE void render_rect(MR_RENDER_RECT_ARGS(MR_ARG_PARAM, MR_ARG_COMMA)) {
  const LaunchParams p = *params;
  const size_t i = get_global_id(0);
  if (i >= (size_t)p.rect.z * (size_t)p.rect.w) return;
  // clang-format off
  const SceneData sc = {nodes, tris, shading, materials, lights, light_cdf, light_pdf_by_prim,
                        texels, textures, srgb_lut, p.light_count, p.environment_eps.xyz,
                        p.environment_eps.w};
  // clang-format on
  const int x = p.rect.x + (int)(i % (size_t)p.rect.z);
  const int y = p.rect.y + (int)(i / (size_t)p.rect.z);
  const uint pixel = (uint)y * p.width + (uint)x;
  float3 sum = (float3)(0.0f);
  uint count = 0;
  const int samples = p.use_spp_map ? (int)spp_map[i] : p.spp;
  for (int s = 0; s < samples; ++s) {
    Rng rng = rng_for_path(pixel, (uint)s, p.frame, p.view, p.seed);
    const float jx = rng_next(&rng), jy = rng_next(&rng);
    const float sx = (((float)x + jx) * p.scale.z - 1.0f) * p.scale.x;
    const float sy = (1.0f - ((float)y + jy) * p.scale.w) * p.scale.y;
    Ray ray;
    ray.org = p.eye.xyz;
    ray.dir = normalize3(p.forward.xyz + p.right.xyz * sx + p.up.xyz * sy);
    ray.tmin = 0.0f;
    ray.tmax = INFINITY;
    const float3 L = trace_path(&sc, ray, &rng, p.max_bounces, p.rr_start, &count);
    sum += finite3(L) ? L : (float3)(0.0f);
  }
  radiance[i] = samples > 0 ? (float4)(sum * (1.0f / (float)samples), 0.0f) : (float4)(0.0f);
  rays[i] = count;
}
