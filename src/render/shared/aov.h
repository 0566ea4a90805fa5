// Feature buffers (AOVs) of the path tracer, written once for every backend in
// render/shared/language.h's dialect: what a denoiser (or Open Image Denoise, Blender's
// compositor) is guided by, captured while the beauty renders (docs/noise.md, "Feature
// buffers"). Only when asked for (RenderSettings::feature_buffers): path_shade() takes a
// null AovSample pointer otherwise and the kernels allocate and store nothing.
//
// Per camera sample (AovSample), at the path's first non-specular vertex: the first
// surface that is not a dielectric (the integrator's only specular BSDF, bsdf.h; mirrors
// and glass are seen through). A path that meets no such surface keeps the first surface
// it met (glass in front of the sky); a camera ray that meets nothing keeps the miss
// values below.
// - albedo: the surface's base colour times its texture (linear RGB, in [0, 1]).
// - normal: the shading normal after the normal map, world space, unit; opaque surfaces
//   (two-sided) face it towards the side the path arrived from.
// - depth: the length of the path from the eye to that vertex (unfolded through mirrors
//   and glass) times the cosine between the camera ray and the camera's axis: for a
//   surface seen directly, its distance along the camera's axis (planar "Z" depth, what
//   OpenEXR's and Blender's Z channels hold), in scene units.
// - emission: the emitted radiance the path collects up to and including that vertex
//   (an emitter seen directly or through mirrors and glass, the environment seen past
//   them), each term weighted exactly as path_shade/path_escape add it to the path's
//   radiance (render/shared/path.h); linear RGB. Light reflected off the vertex (next-event
//   estimation from it, later bounces) is not in it: the beauty minus it is what the
//   denoiser filters (render/shared/denoise.h), the emission added back sharp.
//
// Per pixel (AovPixel, over the pixel's samples, in sample order):
// - albedo: the mean over all samples (a miss counts as 0);
// - normal: the normalised sum over the samples that met a surface; (0, 0, 0) when none;
// - depth: the mean over the samples that met a surface; +infinity when none did;
// - emission: the mean over all samples, each handled as the beauty handles its sample's
//   radiance: 0 when that radiance is not finite, scaled by the same factor when the
//   sample clamp scales it (so it never exceeds the beauty, and a pixel that sees only
//   emitters has exactly the beauty's value);
// - variance: the variance of the pixel's mean luminance less its emission (Rec. 709 Y of
//   each sample's radiance exactly as it is averaged into the beauty, clamped, non-finite
//   as 0, minus that sample's emission as averaged above), i.e. the unbiased sample
//   variance of the samples' Y divided by their count (Welford's recurrence); 0 with fewer
//   than two samples. Less the emission because that is what the denoiser filters, the
//   emission being added back as it is: at a light's edge the emission's own spread (the
//   samples that met the light or missed it) is no noise of the filtered part. Where a
//   pixel sees no emitter, the beauty's variance.
// Every value is a function of the pixel's own samples only, so the buffers are as
// independent of the split as the beauty is.
#ifndef MULTIRAY_RENDER_SHARED_AOV_H
#define MULTIRAY_RENDER_SHARED_AOV_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// Floats per pixel of the packed form (kernels' output, wire): albedo R, G, B (0-2),
// normal X, Y, Z (3-5), depth (6), variance (7), emission R, G, B (8-10).
#define MR_AOV_FLOATS 11

typedef struct {
  mr_float3 albedo, normal;
  mr_float3 emission;  // collected so far, until the first non-specular vertex (done)
  float depth;
  float length;    // of the path so far, up to the last recorded vertex
  float cos_axis;  // between the camera ray and the camera's axis
  bool hit;        // some surface was recorded
  bool done;       // the first non-specular vertex was recorded
} AovSample;

// A camera sample whose ray has unit direction `dir`, the camera's axis `forward` (unit).
MR_DEVICE void aov_init(AovSample* a, mr_float3 dir, mr_float3 forward) {
  a->albedo = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  a->normal = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  a->emission = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  a->depth = INFINITY;
  a->length = 0.0f;
  a->cos_axis = dot3(dir, forward);
  a->hit = false;
  a->done = false;
}

// A surface hit at distance `t` along the path's current ray, with base colour `albedo`
// and shading normal `ns`; `specular`: a dielectric, seen through (the next one counts).
MR_DEVICE void aov_at_hit(AovSample* a, float t, mr_float3 albedo, mr_float3 ns, bool specular) {
  if (a->done) return;
  a->length += t;
  a->albedo = albedo;
  a->normal = ns;
  a->depth = a->length * a->cos_axis;
  a->hit = true;
  a->done = !specular;
}

// Emitted radiance `le` the path adds to its radiance, as it adds it: recorded while the
// first non-specular vertex is still to come or is the one being shaded (path_shade calls
// this before aov_at_hit).
MR_DEVICE void aov_add_emission(AovSample* a, mr_float3 le) {
  if (!a->done) a->emission = a->emission + le;
}

typedef struct {
  mr_float3 albedo, normal;  // sums: over every sample, over the samples that hit
  mr_float3 emission;        // sum over every sample, as averaged into the beauty
  float depth;               // sum over the samples that hit
  float mean, m2;            // Welford's running mean and sum of squared deviations of Y
  mr_int samples, hits;
} AovPixel;

MR_DEVICE void aov_pixel_init(AovPixel* px) {
  px->albedo = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  px->normal = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  px->emission = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  px->depth = 0.0f;
  px->mean = 0.0f;
  px->m2 = 0.0f;
  px->samples = 0;
  px->hits = 0;
}

// Rec. 709 luminance of linear RGB.
MR_DEVICE float aov_luminance(mr_float3 c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// Adds sample `a`, whose radiance is `radiance` as traced and `L` as averaged into the
// beauty: clamp_sample(radiance if finite else 0, limit) (sampling.h), `limit` the sample
// clamp. Its emission gets the same treatment: 0 with a non-finite radiance, else scaled
// by clamp_sample's factor (so, where the emission is all the radiance, the same bits).
MR_DEVICE void aov_pixel_add(AovPixel* px, const AovSample* a, mr_float3 radiance, mr_float3 L,
                             float limit) {
  ++px->samples;
  px->albedo = px->albedo + a->albedo;
  const mr_float3 e = a->emission;
  // The sample's emission as averaged into the pixel's (0 where it is not).
  mr_float3 ec = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  if (finite3(radiance) && finite3(e)) {
    const float m = mr_fmax(radiance.x, mr_fmax(radiance.y, radiance.z));
    ec = limit > 0.0f && m > limit ? e * (limit / m) : e;
    px->emission = px->emission + ec;
  }
  if (a->hit) {
    px->normal = px->normal + a->normal;
    px->depth += a->depth;
    ++px->hits;
  }
  // The variance is that of what the denoiser filters: the beauty less its emission.
  const float y = aov_luminance(L - ec);
  const float delta = y - px->mean;
  px->mean += delta / (float)px->samples;
  px->m2 += delta * (y - px->mean);
}

// The pixel's values in packed order (MR_AOV_FLOATS).
MR_DEVICE void aov_pixel_result(const AovPixel* px, float out[MR_AOV_FLOATS]) {
  const mr_float3 albedo =
      px->samples > 0 ? px->albedo * (1.0f / (float)px->samples) : MR_FLOAT3(0.0f, 0.0f, 0.0f);
  const mr_float3 normal = px->hits > 0 && dot3(px->normal, px->normal) > 0.0f
                               ? normalize3(px->normal)
                               : MR_FLOAT3(0.0f, 0.0f, 0.0f);
  out[0] = albedo.x, out[1] = albedo.y, out[2] = albedo.z;
  out[3] = normal.x, out[4] = normal.y, out[5] = normal.z;
  out[6] = px->hits > 0 ? px->depth / (float)px->hits : INFINITY;
  out[7] = px->samples > 1 ? px->m2 / ((float)(px->samples - 1) * (float)px->samples) : 0.0f;
  const mr_float3 emission =
      px->samples > 0 ? px->emission * (1.0f / (float)px->samples) : MR_FLOAT3(0.0f, 0.0f, 0.0f);
  out[8] = emission.x, out[9] = emission.y, out[10] = emission.z;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_AOV_H
