// The path tracer's integrator, written once for every backend: unidirectional paths with
// next-event estimation, multiple importance sampling (power heuristic) and Russian
// roulette. A path advances a bounce at a time: the backend traces `ray` and calls
// path_shade() with its closest hit or path_escape() without one; the bounce may leave a
// shadow ray in `shadow`, which the backend traces and, when nothing blocks it, adds
// `shadow_contribution` to L (path_shadow_done). How the backend orders that work is its
// own: the CPU runs wavefronts of paths with Embree's packets (render/path_tracer.cpp), an
// OpenCL device one path after another per work-item (kernels/path_tracer.cl).
//
// Sample dimensions (render/shared/sobol.h): one 2D value for the pixel jitter, then per
// bounce a block: for next-event estimation (surfaces that are not dielectrics, when there
// is a light) one value choosing the environment with probability p_env or an emissive
// triangle, and a 2D value placing the sample; a 1D value choosing the BSDF's lobe (drawn
// only when there is a choice, its dimension passed over otherwise) and a 2D value for its
// direction; one value for Russian roulette from `rr_start` on. Each part starts at its
// own dimension, so the image is the same on every device of one type, whatever the split.
//
// SceneData (render/scene_data.h on the CPU; the OpenCL entry point's own) provides what
// surface.h, lights.h and sky.h read, and `light_pdf_by_prim`, `p_env` (0: the
// environment is never sampled) and `eps` (the ray-origin offset).
#ifndef MULTIRAY_RENDER_SHARED_PATH_H
#define MULTIRAY_RENDER_SHARED_PATH_H

#ifdef __cplusplus
#include "render/accel.h"
#include "render/shared/aov.h"
#include "render/shared/bsdf.h"
#include "render/shared/lights.h"
#include "render/shared/sky.h"
#include "render/shared/sobol.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  Ray ray;
  mr_float3 L, beta;
  SampleStream u;  // the path's sample values
  float prev_pdf;
  mr_float3 prev_normal;  // geometric normal at the last vertex (environment MIS)
  bool prev_specular;     // the camera ray counts as specular: emission seen directly
  bool alive;
  bool has_shadow;  // a next-event ray is waiting to be traced
  mr_int depth;
  Ray shadow;
  mr_float3 shadow_contribution;
} PathState;

typedef struct {
  mr_int max_bounces;
  mr_int rr_start;  // the first depth at which Russian roulette may end a path
} PathSettings;

// A camera path with sample stream `u` (its ray set by the caller).
MR_DEVICE void path_init(PathState* p, SampleStream u) {
  p->L = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  p->beta = MR_FLOAT3(1.0f, 1.0f, 1.0f);
  p->u = u;
  p->prev_pdf = 0.0f;
  p->prev_normal = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  p->prev_specular = true;
  p->alive = true;
  p->has_shadow = false;
  p->depth = 0;
}

MR_DEVICE Ray make_ray(mr_float3 org, mr_float3 dir, float tmax) {
  Ray r;
  r.org = org;
  r.dir = dir;
  r.tmin = 0.0f;
  r.tmax = tmax;
  return r;
}

// Light from outside the scene along the ray that just escaped, weighted against
// next-event estimation from the previous vertex.
MR_DEVICE mr_float3 path_escape_contribution(const SceneData* sc, const PathState* p) {
  const mr_float3 le = sky_radiance(sc->sky, sc->sky_map, p->ray.dir);
  float w = 1.0f;
  if (!p->prev_specular && sc->p_env > 0.0f) {
    const float pdf_env = sc->p_env * sky_pdf(sc->sky, sc->sky_tables, p->ray.dir, p->prev_normal);
    w = power_heuristic(p->prev_pdf, pdf_env);
  }
  return p->beta * le * w;
}

// `aov`, when given, takes the environment's light as emission while the path has met
// no non-specular vertex (aov.h).
MR_DEVICE void path_escape(const SceneData* sc, PathState* p, AovSample* aov) {
  const mr_float3 add = path_escape_contribution(sc, p);
  p->L = p->L + add;
  if (aov) aov_add_emission(aov, add);
  p->alive = false;
}

// Adds the waiting shadow ray's light when nothing blocks it.
MR_DEVICE void path_shadow_done(PathState* p, bool blocked) {
  if (!blocked) p->L = p->L + p->shadow_contribution;
  p->has_shadow = false;
}

// The shadow ray towards light direction `wi_world` (local `wi`) and what it brings.
MR_DEVICE void path_set_shadow(PathState* p, const BsdfParams* bsdf, mr_float3 wo, mr_float3 wi,
                               mr_float3 radiance, float pdf_light, Ray shadow) {
  const mr_float3 f = bsdf_eval(bsdf, wo, wi);
  if (!(max3(f) > 0.0f)) return;
  p->shadow = shadow;
  p->shadow_contribution =
      p->beta * f * radiance * (power_heuristic(pdf_light, bsdf_pdf(bsdf, wo, wi)) / pdf_light);
  p->has_shadow = true;
}

// Next-event estimation from a vertex at `pos` with geometric normal `ng`: one sample of
// either the environment or an emissive triangle (three values either way).
MR_DEVICE void path_sample_light(const SceneData* sc, PathState* p, const BsdfParams* bsdf,
                                 const Frame* frame, mr_float3 wo, mr_float3 pos, mr_float3 ng) {
  const float p_env = sc->p_env;
  float ul = sample_1d(&p->u);
  const mr_float2 u12 = sample_2d(&p->u);
  if (ul < p_env) {
    const EnvSample es =
        sky_sample(sc->sky, sc->sky_tables, sc->sky_map, ng, ul / p_env, u12.x, u12.y);
    if (!(es.pdf > 0.0f) || dot3(es.dir, ng) <= 0.0f) return;
    path_set_shadow(p, bsdf, wo, to_local(frame, es.dir), es.radiance, p_env * es.pdf,
                    make_ray(pos + ng * sc->eps, es.dir, INFINITY));
    return;
  }
  ul = (ul - p_env) / (1.0f - p_env);  // exactly ul when there is no environment
  const LightSample ls = sample_light(sc, ul, u12.x, u12.y);
  const mr_float3 d = ls.point - pos;
  const float dist2 = dot3(d, d), dist = mr_sqrt(dist2);
  const mr_float3 wi_world = d * (1.0f / dist);
  const float cos_l = -dot3(ls.normal, wi_world);
  if (!(cos_l > 0.0f) || dot3(wi_world, ng) <= 0.0f) return;
  path_set_shadow(p, bsdf, wo, to_local(frame, wi_world), ls.radiance,
                  (1.0f - p_env) * ls.pdf_area * dist2 / cos_l,
                  make_ray(pos + ng * sc->eps, wi_world, dist * (1.0f - 1e-4f) - sc->eps));
}

// A light sample and the path's continuation from a surface point with BSDF `bsdf`,
// local `frame` and outgoing direction `wo`, at `pos` with geometric normal `ng`.
MR_DEVICE void path_scatter(const SceneData* sc, PathState* p, const BsdfParams* bsdf,
                            const Frame* frame, mr_float3 wo, mr_float3 pos, mr_float3 ng,
                            PathSettings settings) {
  sample_stream_at_bounce(&p->u, p->depth);
  const bool opaque = !bsdf->dielectric;
  if (opaque && (sc->p_env > 0.0f || sc->light_count > 0))
    path_sample_light(sc, p, bsdf, frame, wo, pos, ng);

  sample_stream_at_bounce(&p->u, p->depth);
  p->u.dim += MR_SOBOL_BSDF_OFFSET;
  p->alive = false;
  float u_lobe = 0.0f;
  if (bsdf_chooses_lobe(bsdf))
    u_lobe = sample_1d(&p->u);
  else
    ++p->u.dim;
  const mr_float2 u12 = sample_2d(&p->u);
  BsdfSample bs;
  if (!bsdf_sample(bsdf, wo, u_lobe, u12.x, u12.y, &bs)) return;
  const mr_float3 wi_world = to_world(frame, bs.wi);
  const float side = dot3(wi_world, ng);
  if (opaque && side <= 0.0f) return;  // shading normal leak
  p->beta = p->beta * bs.weight;
  p->prev_pdf = bs.pdf;
  p->prev_specular = bs.specular;
  p->prev_normal = ng;
  p->ray = make_ray(pos + ng * (side > 0.0f ? sc->eps : -sc->eps), wi_world, INFINITY);
  ++p->depth;
  if (p->depth >= settings.rr_start) {
    const float q = rr_survival(max3(p->beta));
    if (q < 1.0f && sample_1d(&p->u) >= q) return;  // (q = 1: nothing to draw)
    p->beta = p->beta * (1.0f / q);
  }
  p->alive = true;
}

// One bounce at `hit`, the closest hit of p->ray on a scene triangle. `base`, when given,
// is the footprint of the hit material's base colour texture (the caller looked it up).
// `aov`, when given, records the sample's feature buffers (aov.h); null: none asked for.
MR_DEVICE void path_shade(const SceneData* sc, PathState* p, const Hit* hit, PathSettings settings,
                          const TexFootprint* base, AovSample* aov) {
  const ShadingRecord d = scene_shading(sc, hit->prim);
  const float w = 1.0f - hit->u - hit->v;
  const mr_float3 pos = p->ray.org + p->ray.dir * hit->t;
  mr_float3 ng = normalize3(hit->ng);
  const mr_float3 n = d.normal[0] * w + d.normal[1] * hit->u + d.normal[2] * hit->v;
  mr_float3 ns = dot3(n, n) > 0.0f ? normalize3(n) : ng;
  if (dot3(ns, ng) < 0.0f) ns = -ns;
  const mr_float2 uv = shading_uv(&d, w, hit->u, hit->v);
  const MR_GLOBAL MaterialRecord* mat = &sc->materials[d.material];
  const mr_float3 wo_world = -p->ray.dir;
  const bool front = dot3(ng, wo_world) > 0.0f;

  // A path at its last bounce still records its features when they are waiting for it.
  const bool record = aov && !aov->done;
  if (front && mat->emissive) {
    const mr_float3 le = emission_at(sc, mat, uv);
    mr_float3 add;
    if (p->prev_specular) {
      add = p->beta * le;
    } else {
      const float cos_l = dot3(ng, wo_world);
      const float pdf_light =
          (1.0f - sc->p_env) * sc->light_pdf_by_prim[hit->prim] * hit->t * hit->t / cos_l;
      add = p->beta * le * power_heuristic(p->prev_pdf, pdf_light);
    }
    p->L = p->L + add;
    if (aov) aov_add_emission(aov, add);  // until the first non-specular vertex
  }
  if (p->depth >= settings.max_bounces && !record) {
    p->alive = false;
    return;
  }

  const SurfacePoint sp = surface_at(sc, mat, uv, ns, ng, hit->prim, base);
  ns = sp.ns;
  const BsdfParams bsdf =
      bsdf_params(sp.base_color, sp.metallic, sp.roughness, mat->ior, mat->dielectric != 0u);
  // Opaque surfaces are two-sided: face the normals towards the viewer. Dielectrics keep
  // their outward normal so the BSDF knows whether the path is inside.
  const bool opaque = !bsdf.dielectric;
  if (opaque && !front) {
    ng = -ng;
    ns = -ns;
  }
  if (record) {
    aov_at_hit(aov, hit->t, sp.base_color, ns, !opaque);
    if (p->depth >= settings.max_bounces) {
      p->alive = false;
      return;
    }
  }
  Frame frame = frame_from_normal(ns);
  mr_float3 wo = to_local(&frame, wo_world);
  if (opaque && wo.z <= 0.0f) {
    frame = frame_from_normal(ng);  // the shading normal faces away: fall back
    wo = to_local(&frame, wo_world);
  }
  path_scatter(sc, p, &bsdf, &frame, wo, pos, ng, settings);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_PATH_H
