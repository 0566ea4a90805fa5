// SVGF's temporal accumulation for one pixel (Schied et al., "Spatiotemporal
// Variance-Guided Filtering: Real-Time Reconstruction for Path-Traced Global
// Illumination", HPG 2017): the pixel's surface point is found in the previous frame
// through both cameras, the previous frame's accumulated colour and luminance moments are
// read there where that frame saw the same surface (depth and normal agree), and blended
// with the current frame's. Written in render/shared/language.h's dialect; buffers as in
// render/shared/denoise.h (colours demodulated).
#ifndef MULTIRAY_RENDER_SHARED_DENOISE_TEMPORAL_H
#define MULTIRAY_RENDER_SHARED_DENOISE_TEMPORAL_H

#ifdef __cplusplus
#include "render/shared/camera.h"
#include "render/shared/denoise.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct {
  float alpha;             // least weight of the current frame in the colour (SVGF: 0.2)
  float moments_alpha;     // the same for the moments (SVGF: 0.2)
  float depth_tolerance;   // a previous depth within this fraction of the expected is a match
  float normal_tolerance;  // ... and a normal whose cosine to the current is at least this
  int has_given_variance;  // frame_variance is the renderer's, not the spatial estimate
} TemporalParams;

// Where `d` lands in camera `c`'s image, in pixels (x right, y down): `d` a point, or with
// `is_direction` a direction (a point at infinity: what a miss saw). False behind the
// camera. Also the depth along its axis in `z` (of a direction: its cosine to the axis).
MR_DEVICE bool denoise_project(const CameraBlock* c, mr_float3 d, int is_direction, float* px,
                               float* py, float* z) {
  const mr_float3 v = is_direction ? d : d - MR_XYZ(c->eye);
  *z = dot3(v, MR_XYZ(c->forward));
  if (!(*z > 0.0f)) return false;
  const float sx = dot3(v, MR_XYZ(c->right)) / (*z * c->scale.x);
  const float sy = dot3(v, MR_XYZ(c->up)) / (*z * c->scale.y);
  *px = (sx + 1.0f) / c->scale.z;
  *py = (1.0f - sy) / c->scale.w;
  return true;
}

// Whether previous pixel `q` saw the surface of the current pixel (miss or not; depth
// `z` expected in the previous camera; normal `n`).
MR_DEVICE bool denoise_history_matches(const MR_GLOBAL float* prev_depth,
                                       const MR_GLOBAL float* prev_normal, int q, bool miss,
                                       float z, mr_float3 n, const TemporalParams* t) {
  const bool prev_miss = denoise_is_miss(prev_depth, q);
  if (miss || prev_miss) return miss && prev_miss;
  return mr_fabs(prev_depth[q] - z) <= t->depth_tolerance * z &&
         dot3(load3(prev_normal + 3 * q), n) >= t->normal_tolerance;
}

// The previous frame's state at pixel `i` of the current frame, bilinear over the four
// previous pixels around where its surface was seen, those that match only. Returns the
// weight found (0: no history: a disocclusion, or the point was outside the previous
// image); `hist` then holds colour, and `m` (m1, m2) and `hv` (history length, variance).
MR_DEVICE float denoise_reproject(
    const CameraBlock* cur, const CameraBlock* prev, const MR_GLOBAL float* depth,
    const MR_GLOBAL float* normal, const MR_GLOBAL float* prev_color,
    const MR_GLOBAL float* prev_moments, const MR_GLOBAL float* prev_history,
    const MR_GLOBAL float* prev_depth, const MR_GLOBAL float* prev_normal, int width, int height,
    int x, int y, const TemporalParams* t, mr_float3* hist, mr_float2* m, mr_float2* hv) {
  const int i = y * width + x;
  const bool miss = denoise_is_miss(depth, i);
  const mr_float3 dir = camera_dir(cur, (float)x + 0.5f, (float)y + 0.5f);
  const mr_float3 d =
      miss ? dir : MR_XYZ(cur->eye) + dir * (depth[i] / dot3(dir, MR_XYZ(cur->forward)));
  float px, py, z;
  if (!denoise_project(prev, d, miss, &px, &py, &z)) return 0.0f;
  const mr_float3 n = load3(normal + 3 * i);
  const float fx = px - 0.5f, fy = py - 0.5f;
  if (!(fx > -1.0f && fy > -1.0f && fx < (float)width && fy < (float)height)) return 0.0f;
  const int x0 = (int)mr_floor(fx), y0 = (int)mr_floor(fy);
  const float tx = fx - (float)x0, ty = fy - (float)y0;
  float sum = 0.0f;
  *hist = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  *m = MR_FLOAT2(0.0f, 0.0f);
  *hv = MR_FLOAT2(0.0f, 0.0f);
  for (int k = 0; k < 4; ++k) {
    const int qx = x0 + (k & 1), qy = y0 + (k >> 1);
    if (qx < 0 || qx >= width || qy < 0 || qy >= height) continue;
    const int q = qy * width + qx;
    if (!denoise_history_matches(prev_depth, prev_normal, q, miss, z, n, t)) continue;
    const float w = ((k & 1) ? tx : 1.0f - tx) * ((k >> 1) ? ty : 1.0f - ty);
    sum += w;
    *hist = *hist + load3(prev_color + 3 * q) * w;
    *m = MR_FLOAT2(m->x + prev_moments[2 * q] * w, m->y + prev_moments[2 * q + 1] * w);
    *hv = MR_FLOAT2(hv->x + prev_history[2 * q] * w, hv->y + prev_history[2 * q + 1] * w);
  }
  // Below 1% of a pixel's weight the history is too thin to trust (and to divide by).
  if (sum < 0.01f) return 0.0f;
  *hist = *hist * (1.0f / sum);
  *m = MR_FLOAT2(m->x / sum, m->y / sum);
  *hv = MR_FLOAT2(hv->x / sum, hv->y / sum);
  return sum;
}

// Whether a history of `n` frames (this one included) is too young for its moments'
// variance (SVGF: under four frames), so that the frame's variance is the spatial estimate
// (render/shared/denoise_atrous.h) when the renderer gave none.
MR_DEVICE int denoise_history_young(float n) { return n < 4.0f; }

// The variance of an accumulation whose current frame has weight `a`: the history's
// variance `prev` and the frame's `v` carried as for a weighted mean of independent
// frames, (1 - a)^2 prev + a^2 v.
MR_DEVICE float denoise_blend_variance(float prev, float a, float v) {
  return (1.0f - a) * (1.0f - a) * prev + a * a * v;
}

// The same for a young history (denoise_history_young) whose frame variance was taken as
// 0 in the temporal step, so that the spatial estimate is made only for such pixels
// (render/denoise.cpp): `history_part` is what denoise_blend_variance gave with v = 0,
// i.e. (1 - a)^2 prev to the bit (adding +0 changes nothing), and this adds a^2 v, the
// same bits denoise_blend_variance gives with v. `n` is the history length the temporal
// step wrote (exact under its cap) and `alpha` its TemporalParams::alpha.
MR_DEVICE float denoise_young_history_variance(float history_part, float n, float alpha, float v) {
  const float a = mr_fmax(alpha, 1.0f / n);
  return history_part + a * a * v;
}

// Accumulates pixel (x, y): the current demodulated colour blended into its reprojected
// history with weight max(alpha, 1 / n) (n: frames in the history, this one included, so
// a young history is a plain mean), the luminance moments likewise. Writes colour,
// moments (m1, m2) and (n, variance of the accumulated colour's luminance): the frame's
// variance (the renderer's when given; else the moments' from 4 frames on, the spatial
// estimate in `frame_variance` before) carried through the blend as for a weighted mean
// of independent frames, (1 - a)^2 v_prev + a^2 v_frame. `has_previous` 0: no history.
MR_DEVICE void denoise_temporal_pixel(
    const CameraBlock* cur, const CameraBlock* prev, int has_previous,
    const MR_GLOBAL float* color, const MR_GLOBAL float* frame_variance,
    const MR_GLOBAL float* depth, const MR_GLOBAL float* normal, const MR_GLOBAL float* prev_color,
    const MR_GLOBAL float* prev_moments, const MR_GLOBAL float* prev_history,
    const MR_GLOBAL float* prev_depth, const MR_GLOBAL float* prev_normal,
    MR_GLOBAL float* out_color, MR_GLOBAL float* out_moments, MR_GLOBAL float* out_history,
    int width, int height, int x, int y, const TemporalParams* t) {
  const int i = y * width + x;
  mr_float3 hist = MR_FLOAT3(0.0f, 0.0f, 0.0f);
  mr_float2 m = MR_FLOAT2(0.0f, 0.0f), hv = MR_FLOAT2(0.0f, 0.0f);
  const float found =
      has_previous
          ? denoise_reproject(cur, prev, depth, normal, prev_color, prev_moments, prev_history,
                              prev_depth, prev_normal, width, height, x, y, t, &hist, &m, &hv)
          : 0.0f;
  const float n = found > 0.0f ? mr_fmax(1.0f, hv.x) + 1.0f : 1.0f;
  const float a = mr_fmax(t->alpha, 1.0f / n), am = mr_fmax(t->moments_alpha, 1.0f / n);
  const mr_float3 c = load3(color + 3 * i);
  const float l = denoise_luminance(c);
  const mr_float3 blended = lerp3(hist, c, a);
  const float m1 = m.x * (1.0f - am) + l * am, m2 = m.y * (1.0f - am) + l * l * am;
  float v = frame_variance[i];
  if (!t->has_given_variance && !denoise_history_young(n)) v = mr_fmax(0.0f, m2 - m1 * m1);
  out_color[3 * i] = blended.x;
  out_color[3 * i + 1] = blended.y;
  out_color[3 * i + 2] = blended.z;
  out_moments[2 * i] = m1;
  out_moments[2 * i + 1] = m2;
  // The history length is capped where it no longer changes the weights (1 / n < alpha).
  out_history[2 * i] = n < 1024.0f ? n : 1024.0f;
  out_history[2 * i + 1] = denoise_blend_variance(hv.y, a, v);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_TEMPORAL_H
