// The environment light of render/environment.cpp, operation for operation: radiance
// along a direction, the density of sampling it, and the sample itself (the sun's cone,
// the map's piecewise-constant distribution from the host's tables, or cosine-weighted
// around the normal for a constant sky). Directions point away from the scene. The map's
// geometry and sampling are render/shared/environment.h's, the warps sampling.h's; what
// is left here reads them from the host's Sky block.

typedef struct {
  float3 dir;  // towards the light, unit
  float3 radiance;
  float pdf;  // solid angle, with the choice between sun and sky
} EnvSample;

float3 sky_frame_x(const __global Sky* s) { return load3(s->frame_x); }
float3 sky_frame_up(const __global Sky* s) { return load3(s->frame_up); }
float3 sky_frame_z(const __global Sky* s) { return load3(s->frame_z); }

// render/environment.h's direction_to_equirect and equirect_to_direction.
float2 direction_to_equirect(const __global Sky* s, float3 d) {
  return equirect_uv(sky_frame_x(s), sky_frame_up(s), sky_frame_z(s), d);
}

float3 equirect_to_direction(const __global Sky* s, float2 uv) {
  return equirect_direction(sky_frame_x(s), sky_frame_up(s), sky_frame_z(s), uv);
}

// The map pixel holding `uv`, as an index into its width x height tables.
uint map_pixel(const __global Sky* s, float2 uv) {
  const int x = equirect_texel(uv.x, s->map_width), y = equirect_texel(uv.y, s->map_height);
  return (uint)y * (uint)s->map_width + (uint)x;
}

float3 sky_radiance(const SceneData* sc, float3 dir) {
  const __global Sky* s = sc->sky;
  float3 L = load3(s->constant_sky);
  if (s->map_width > 0)
    L += load3(sc->sky_data + s->map + 3u * map_pixel(s, direction_to_equirect(s, dir)));
  if (s->sun_on && dot3(dir, load3(s->sun_dir)) >= s->sun_cos) L += load3(s->sun_radiance);
  return L;
}

// EnvironmentLight::map_pdf.
float map_pdf(const SceneData* sc, float2 uv) {
  const __global Sky* s = sc->sky;
  const int w = s->map_width, h = s->map_height;
  const int y = equirect_texel(uv.y, h);
  return equirect_pdf(sc->sky_data[s->row_pdf + (uint)y],
                      sc->sky_data[s->pix_pdf + map_pixel(s, uv)], w, h, uv.y);
}

// EnvironmentLight::pdf: density with which sky_sample(n, ...) returns `dir`.
float sky_pdf(const SceneData* sc, float3 dir, float3 n) {
  const __global Sky* s = sc->sky;
  float sky = 0.0f;
  if (s->sky_on) {
    if (s->map_width > 0) {
      sky = map_pdf(sc, direction_to_equirect(s, dir));
    } else {
      sky = fmax(dot3(dir, n), 0.0f) * INV_PI;
    }
  }
  float p = (1.0f - s->p_sun) * sky;
  if (s->sun_on && dot3(dir, load3(s->sun_dir)) >= s->sun_cos) p += s->p_sun * s->sun_pdf;
  return p;
}

EnvSample sky_sample(const SceneData* sc, float3 n, float u_choice, float u1, float u2) {
  const __global Sky* s = sc->sky;
  EnvSample es;
  if (u_choice < s->p_sun) {
    // Uniform in the cone around the sun's direction.
    const Frame f = frame_from_normal(load3(s->sun_dir));
    es.dir = normalize3(to_world(&f, sample_cone(s->sun_cos, u1, u2)));
  } else if (s->map_width > 0) {
    es.dir = equirect_to_direction(
        s, sample_equirect(sc->sky_data + s->row_cdf, sc->sky_data + s->col_cdf,
                           (uint)s->map_width, (uint)s->map_height, u1, u2));
  } else {
    const Frame f = frame_from_normal(n);
    es.dir = to_world(&f, sample_cosine_hemisphere(u1, u2));
  }
  es.pdf = sky_pdf(sc, es.dir, n);
  es.radiance = sky_radiance(sc, es.dir);
  return es;
}
