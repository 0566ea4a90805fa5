// The environment light (render/environment.h) as the integrator evaluates it, written
// once for every backend: radiance along a direction, the density of sampling it, and the
// sample itself (the sun's cone, the map's piecewise-constant distribution, or
// cosine-weighted around the normal for a constant sky). Directions point away from the
// scene. `tables` holds the map's sampling tables at the record's offsets, `map` its
// radiance (3 floats a pixel, times s->map_scale when read); both unused without a map.
#ifndef MULTIRAY_RENDER_SHARED_SKY_H
#define MULTIRAY_RENDER_SHARED_SKY_H

#ifdef __cplusplus
#include "render/shared/environment.h"
#include "render/shared/sampling.h"
#include "render/shared/scene_records.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  mr_float3 dir;  // towards the light, unit
  mr_float3 radiance;
  float pdf;  // solid angle, with the choice between sun and sky
} EnvSample;

MR_DEVICE mr_float2 sky_uv(const MR_GLOBAL SkyRecord* s, mr_float3 d) {
  return equirect_uv(load3(s->frame_x), load3(s->frame_up), load3(s->frame_z), d);
}

// The map pixel holding `uv`, as an index into its width x height tables.
MR_DEVICE mr_uint sky_pixel(const MR_GLOBAL SkyRecord* s, mr_float2 uv) {
  const mr_int x = equirect_texel(uv.x, s->map_width), y = equirect_texel(uv.y, s->map_height);
  return (mr_uint)y * (mr_uint)s->map_width + (mr_uint)x;
}

MR_DEVICE bool sky_sun_holds(const MR_GLOBAL SkyRecord* s, mr_float3 dir) {
  return s->sun_on && dot3(dir, load3(s->sun_dir)) >= s->sun_cos;
}

// Radiance arriving along -`dir` from outside.
MR_DEVICE mr_float3 sky_radiance(const MR_GLOBAL SkyRecord* s, const MR_GLOBAL float* map,
                                 mr_float3 dir) {
  mr_float3 L = load3(s->constant_sky);
  if (s->map_width > 0) L = L + load3(map + 3u * sky_pixel(s, sky_uv(s, dir))) * s->map_scale;
  if (sky_sun_holds(s, dir)) L = L + load3(s->sun_radiance);
  return L;
}

// Density with which sky_sample(n, ...) returns `dir`.
MR_DEVICE float sky_pdf(const MR_GLOBAL SkyRecord* s, const MR_GLOBAL float* tables, mr_float3 dir,
                        mr_float3 n) {
  float sky = 0.0f;
  if (s->sky_on) {
    if (s->map_width > 0) {
      const mr_float2 uv = sky_uv(s, dir);
      const mr_int y = equirect_texel(uv.y, s->map_height);
      sky = equirect_pdf(tables[s->row_pdf + (mr_uint)y], tables[s->pix_pdf + sky_pixel(s, uv)],
                         s->map_width, s->map_height, uv.y);
    } else {
      sky = mr_fmax(dot3(dir, n), 0.0f) * MR_INV_PI;
    }
  }
  float p = (1.0f - s->p_sun) * sky;
  if (sky_sun_holds(s, dir)) p += s->p_sun * s->sun_pdf;
  return p;
}

// One sample for a shading point with geometric normal `n`: `u_choice` picks sun or sky.
MR_DEVICE EnvSample sky_sample(const MR_GLOBAL SkyRecord* s, const MR_GLOBAL float* tables,
                               const MR_GLOBAL float* map, mr_float3 n, float u_choice, float u1,
                               float u2) {
  EnvSample es;
  if (u_choice < s->p_sun) {
    // Uniform in the cone around the sun's direction.
    const Frame f = frame_from_normal(load3(s->sun_dir));
    es.dir = normalize3(to_world(&f, sample_cone(s->sun_cos, u1, u2)));
  } else if (s->map_width > 0) {
    es.dir =
        equirect_direction(load3(s->frame_x), load3(s->frame_up), load3(s->frame_z),
                           sample_equirect(tables + s->row_cdf, tables + s->col_cdf,
                                           (mr_uint)s->map_width, (mr_uint)s->map_height, u1, u2));
  } else {
    const Frame f = frame_from_normal(n);
    es.dir = to_world(&f, sample_cosine_hemisphere(u1, u2));
  }
  es.pdf = sky_pdf(s, tables, es.dir, n);
  es.radiance = sky_radiance(s, map, es.dir);
  return es;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SKY_H
