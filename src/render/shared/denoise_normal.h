// The denoiser's normal term on curved surfaces (render/shared/denoise.h has the filter,
// its buffers and its credits), written in render/shared/language.h's dialect for the CPU
// and OpenCL alike.
//
// The term compares a tap q's normal with the centre p's. On a plane the two agree, and
// cos(angle)^sigma_normal (SVGF's 128) stops the filter at a crease. On a curved surface
// (a column, an arch, a moulding) the shading normal turns steadily from pixel to pixel,
// by 10-20 degrees at a few hundred pixels a frame, and cos^128 (0.14 at 10 degrees, 4e-4
// at 20) then shuts out every neighbour: a pixel whose samples all missed the light stays
// black (issue 52, docs/noise.md). So the term allows for the turn p's own surface
// predicts, as the depth term allows for p's plane (denoise_slope): p's turn per pixel
// along x and along y, each the smaller of its one-sided differences, so that a crease
// beside p (one side turning sharply, the other not) predicts no turn and still stops
// the filter; only the turn beyond the prediction is weighted down.
//
// Turns are measured as chords: |n_q - n_p| = 2 sin(angle / 2) between unit normals, a
// distance on the sphere of directions, so the triangle inequality bounds the chord over
// (dx, dy) by |dx| turn_x + |dy| turn_y (exact along an axis for small turns, 2 sin(k a/2)
// <= 2 k sin(a/2) for a steady turn of a per pixel over k pixels). That bound is the
// prediction: an upper bound, since only the turn's size per axis is kept, not its
// direction (a cylinder seen slanting turns along x and y at once, yet not along the
// diagonal between). What lies beyond it, the chord e = max(0, |n_q - n_p| - predicted),
// is turned back into a cosine, 1 - e^2 / 2 (the cosine of the angle whose chord is e),
// and that cosine is raised to sigma_normal: sigma_normal keeps its meaning, the exponent
// of the cosine of the angle by which q's normal turns beyond what p's surface predicts.
// Where p predicts no turn (a plane, a crease beside it) that cosine is q's cosine itself,
// to the bit.
#ifndef MULTIRAY_RENDER_SHARED_DENOISE_NORMAL_H
#define MULTIRAY_RENDER_SHARED_DENOISE_NORMAL_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// The chord between two unit normals whose cosine is `cosine`: sqrt(2 - 2 cosine), 0
// where rounding makes the square negative (a select on values, see denoise_tap_weight).
MR_DEVICE float denoise_normal_chord(float cosine) {
  const float square = 2.0f - 2.0f * cosine;
  return mr_sqrt(square > 0.0f ? square : 0.0f);
}

// p's turn of the normal per pixel along one axis (a chord, denoise_normal_chord): of the
// chords to the neighbours before (`i - stride`) and after (`i + stride`), where they
// exist and are hits (`depth` finite), the smaller one; 0 when neither is, or p is a miss.
// The smaller, as denoise_slope's: a crease on one side of p does not bend its surface.
MR_DEVICE float denoise_normal_turn(const MR_GLOBAL float* normal, const MR_GLOBAL float* depth,
                                    int i, int stride, int has_before, int has_after) {
  const mr_float3 n = load3(normal + 3 * i);
  const int hit = depth[i] < INFINITY;
  const int before = hit && has_before && depth[i - stride] < INFINITY;
  const int after = hit && has_after && depth[i + stride] < INFINITY;
  const float cb = before ? denoise_normal_chord(dot3(n, load3(normal + 3 * (i - stride)))) : 0.0f;
  const float ca = after ? denoise_normal_chord(dot3(n, load3(normal + 3 * (i + stride)))) : 0.0f;
  if (before && after) return cb < ca ? cb : ca;
  return before ? cb : ca;
}

// The cosine the normal weight raises to sigma_normal for a tap (dx, dy) pixels from p
// whose normal's cosine to p's is `cosine`, p's turns per pixel being `turn_x` and
// `turn_y` (denoise_normal_turn): 1 where the chord between the normals is within the
// predicted |dx| turn_x + |dy| turn_y, else the cosine of the chord beyond it (the file's
// comment); `cosine` itself where it is not positive (normals facing apart never mix) or
// nothing is predicted. Branch-free, selects one after the other on values (see
// denoise_tap_weight), so the CPU's blocks vectorise it.
MR_DEVICE float denoise_normal_cosine(float cosine, float turn_x, float turn_y, int dx, int dy) {
  const float chord = denoise_normal_chord(cosine);
  const float predicted = turn_x * mr_fabs((float)dx) + turn_y * mr_fabs((float)dy);
  // 1 - (chord - predicted)^2 / 2 with chord^2 = 2 - 2 cosine: exactly `cosine` when
  // predicted is 0.
  const float beyond = cosine + predicted * (chord - 0.5f * predicted);
  const float relaxed = chord > predicted ? beyond : 1.0f;
  return cosine > 0.0f ? relaxed : cosine;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_DENOISE_NORMAL_H
