// The environment light of render/environment.cpp, operation for operation: radiance
// along a direction, the density of sampling it, and the sample itself (the sun's cone,
// the map's piecewise-constant distribution from the host's tables, or cosine-weighted
// around the normal for a constant sky). Directions point away from the scene.

typedef struct {
  float3 dir;  // towards the light, unit
  float3 radiance;
  float pdf;  // solid angle, with the choice between sun and sky
} EnvSample;

float3 sky_frame_x(const __global Sky* s) { return load3(s->frame_x); }
float3 sky_frame_up(const __global Sky* s) { return load3(s->frame_up); }
float3 sky_frame_z(const __global Sky* s) { return load3(s->frame_z); }

// direction_to_equirect: u right, v down, both in [0, 1].
float2 direction_to_equirect(const __global Sky* s, float3 d) {
  const float lx = dot3(d, sky_frame_x(s)), ly = dot3(d, sky_frame_up(s)),
              lz = dot3(d, sky_frame_z(s));
  const float phi = atan2(lx, -lz);  // 0 along -z, pi/2 along +x
  const float theta = acos(clamp(ly, -1.0f, 1.0f));
  return (float2)(0.5f + phi * (0.5f * INV_PI), theta * INV_PI);
}

float3 equirect_to_direction(const __global Sky* s, float2 uv) {
  const float phi = (uv.x - 0.5f) * 2.0f * PI, theta = uv.y * PI;
  const float st = sin(theta);
  return sky_frame_x(s) * (st * sin(phi)) + sky_frame_up(s) * cos(theta) -
         sky_frame_z(s) * (st * cos(phi));
}

// The map pixel holding `uv`, as an index into its width x height tables.
uint map_pixel(const __global Sky* s, float2 uv) {
  const int w = s->map_width, h = s->map_height;
  const int x = clamp((int)(uv.x * (float)w), 0, w - 1);
  const int y = clamp((int)(uv.y * (float)h), 0, h - 1);
  return (uint)y * (uint)w + (uint)x;
}

float3 sky_radiance(const SceneData* sc, float3 dir) {
  const __global Sky* s = sc->sky;
  float3 L = load3(s->constant_sky);
  if (s->map_width > 0) L += load3(sc->sky_data + s->map + 3u * map_pixel(s, direction_to_equirect(s, dir)));
  if (s->sun_on && dot3(dir, load3(s->sun_dir)) >= s->sun_cos) L += load3(s->sun_radiance);
  return L;
}

// EnvironmentLight::map_pdf: pixel probability x pixel count over the Jacobian of the
// equirectangular map (2 pi^2 sin theta).
float map_pdf(const SceneData* sc, float2 uv) {
  const __global Sky* s = sc->sky;
  const int w = s->map_width, h = s->map_height;
  const int x = clamp((int)(uv.x * (float)w), 0, w - 1);
  const int y = clamp((int)(uv.y * (float)h), 0, h - 1);
  const float st = sin(uv.y * PI);
  if (!(st > 0.0f)) return 0.0f;
  const float p = sc->sky_data[s->row_pdf + (uint)y] *
                  sc->sky_data[s->pix_pdf + (uint)y * (uint)w + (uint)x] * (float)w * (float)h;
  return p / (2.0f * PI * PI * st);
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

// Index of the first of cdf[0, n) greater than u (the last if none), as std::upper_bound.
uint pick_cdf(const __global float* cdf, uint n, float u) {
  uint lo = 0, hi = n;
  while (lo < hi) {
    const uint mid = lo + (hi - lo) / 2;
    if (u < cdf[mid]) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return min(lo, n - 1);
}

EnvSample sky_sample(const SceneData* sc, float3 n, float u_choice, float u1, float u2) {
  const __global Sky* s = sc->sky;
  EnvSample es;
  if (u_choice < s->p_sun) {
    // Uniform in the cone around the sun's direction.
    const float cos_t = 1.0f - u1 * (1.0f - s->sun_cos);
    const float sin_t = sqrt(fmax(0.0f, 1.0f - cos_t * cos_t));
    const float phi = 2.0f * PI * u2;
    const Frame f = frame_from_normal(load3(s->sun_dir));
    es.dir = normalize3(to_world(&f, (float3)(sin_t * cos(phi), sin_t * sin(phi), cos_t)));
  } else if (s->map_width > 0) {
    const uint w = (uint)s->map_width, h = (uint)s->map_height;
    const __global float* rows = sc->sky_data + s->row_cdf;
    const uint y = pick_cdf(rows, h, u1);
    const __global float* row = sc->sky_data + s->col_cdf + y * w;
    const uint x = pick_cdf(row, w, u2);
    // Where inside the pixel: the part of u2 (and u1) past the chosen bin's start.
    const float r0 = y == 0 ? 0.0f : rows[y - 1], c0 = x == 0 ? 0.0f : row[x - 1];
    const float fy = clamp((u1 - r0) / fmax(rows[y] - r0, 1e-20f), 0.0f, 1.0f);
    const float fx = clamp((u2 - c0) / fmax(row[x] - c0, 1e-20f), 0.0f, 1.0f);
    es.dir = equirect_to_direction(
        s, (float2)(((float)x + fx) / (float)w, ((float)y + fy) / (float)h));
  } else {
    const Frame f = frame_from_normal(n);
    es.dir = to_world(&f, sample_cosine_hemisphere(u1, u2));
  }
  es.pdf = sky_pdf(sc, es.dir, n);
  es.radiance = sky_radiance(sc, es.dir);
  return es;
}
