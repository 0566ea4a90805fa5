// The transfer function's lookup as the volume raycaster (render/shared/volume.h) samples
// it, written once for every backend in render/shared/language.h's dialect. The table
// (VolumeStyle::colour_log_transparency) holds per entry linear RGB and log(1 - alpha) at the
// reference step, entries evenly spaced over the data values.
#ifndef MULTIRAY_RENDER_SHARED_TRANSFER_H
#define MULTIRAY_RENDER_SHARED_TRANSFER_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// std::clamp's definition, written out (OpenCL C's clamp is fmin(fmax(...)), which differs
// for NaN): both raycasters clamp with it.
MR_DEVICE float clamp_std(float v, float lo, float hi) { return v < lo ? lo : (hi < v ? hi : v); }

// A table entry interpolated: colour and log transparency (0: fully transparent).
typedef struct {
  mr_float3 colour;
  float log_t;
} TfSample;

// The fractional table position of data `value`, for a table of `last` + 1 entries
// starting at data value `lo` with `to_index` entries per unit of data; clamped to the table.
MR_DEVICE float tf_position(float value, float lo, float to_index, mr_uint last) {
  return clamp_std((value - lo) * to_index, 0.0f, (float)last);
}

// The table linearly interpolated at position `fi` in [0, last].
MR_DEVICE TfSample tf_lookup(const MR_GLOBAL mr_float4* table, mr_uint last, float fi) {
  const mr_uint i0 = (mr_uint)fi, i1 = i0 + 1 < last ? i0 + 1 : last;
  const mr_float4 c0 = table[i0], c1 = table[i1];
  const float f = fi - (float)i0;
  TfSample s;
  s.log_t = c0.w + (c1.w - c0.w) * f;
  s.colour =
      MR_FLOAT3(c0.x + (c1.x - c0.x) * f, c0.y + (c1.y - c0.y) * f, c0.z + (c1.z - c0.z) * f);
  return s;
}

// Opacity of a sample of log transparency `log_t` over a step of `ratio` reference steps:
// 1 - (1 - alpha)^ratio (opacity correction, Engel et al., "Real-Time Volume Graphics"
// §1.4.3), without a pow.
MR_DEVICE float tf_opacity(float log_t, float ratio) { return -mr_expm1(log_t * ratio); }

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_TRANSFER_H
