// Decoding of the compact scene (render/compact_quantize.h, compact_scene.h), written once
// for the CPU's compact traversal and shading and for the OpenCL kernel built with
// -DMR_COMPACT=1 (kernels/shading.cl, traverse_compact.cl), in render/shared/language.h's
// dialect, so both backends decode every position, normal, uv and box plane with the same
// arithmetic. The encoders (host only) are in render/compact_quantize.cpp and
// compact_scene.cpp.
#ifndef MULTIRAY_RENDER_SHARED_COMPACT_H
#define MULTIRAY_RENDER_SHARED_COMPACT_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// A vertex (Seo, Park & Ihm 2022, §3): a 16-bit index into the cell-index table, which
// lists only the geometry cells (cells holding a vertex) as three 16-bit cell coordinates
// each, and three 10-bit offsets inside that cell packed in `offsets` (x in bits 0-9, y in
// 10-19, z in 20-29; 1023 is the cell's far side, `step` = cell / 1023 apart). `cells` is
// the table; the grid's cubic cells of side `cell` start at `origin`. The encoder makes
// `cell` a float of 8 significant bits and `origin` a multiple of its last bit, so the
// cell's corner origin + cell * coordinate is exact and the only rounding that matters is
// the last addition's, at the magnitude of the vertex itself: a fine grid far from the
// origin keeps its precision.
MR_DEVICE mr_float3 compact_decode_position(mr_float3 origin, float cell, float step,
                                            const MR_GLOBAL mr_ushort* cells, mr_uint index,
                                            mr_uint offsets) {
  const MR_GLOBAL mr_ushort* c = cells + 3u * index;
  return MR_FLOAT3(origin.x + cell * (float)c[0] + step * (float)(offsets & 1023u),
                   origin.y + cell * (float)c[1] + step * (float)((offsets >> 10) & 1023u),
                   origin.z + cell * (float)c[2] + step * (float)((offsets >> 20) & 1023u));
}

// Value `index` of an array of `width`-bit unsigned values (0..32 bits) packed end to end,
// least significant bit first, into 32-bit words: the faces' vertex indices, the material
// ids and the uv shifts are stored so, each in as many bits as its largest value needs,
// and every value stays one or two word reads away (random access, as the paper requires).
// A width of 0 reads no memory and gives 0 (every value equal, nothing stored).
MR_DEVICE mr_uint compact_read_bits(const MR_GLOBAL mr_uint* words, mr_ulong index,
                                    mr_uint width) {
  if (width == 0u) return 0u;
  const mr_ulong bit = index * (mr_ulong)width;
  const mr_ulong word = bit >> 5;
  const mr_uint shift = (mr_uint)(bit & 31u);
  mr_uint v = words[word] >> shift;
  if (shift + width > 32u) v |= words[word + 1u] << (32u - shift);
  return width == 32u ? v : (v & ((1u << width) - 1u));
}

// A triangle's integer uv shift along `axis` (0: u, 1: v) from its packed entry: u's
// offset from the scene's smallest u shift in the low `bits_u` bits, v's above them
// (each at most 16 bits: shifts are int16).
MR_DEVICE mr_int compact_uv_shift(mr_uint entry, mr_uint bits_u, mr_int base, mr_uint axis) {
  const mr_uint offset = axis == 0u ? (entry & ((1u << bits_u) - 1u)) : (entry >> bits_u);
  return base + (mr_int)offset;
}

// One texture coordinate of a triangle's corner. The vertex stores its coordinate modulo
// the scene's period 2^period_log2 in 16-bit steps of `step` (= 2^period_log2 / 65536); the
// triangle stores its integer shift (the floor of its smallest coordinate). The code
// relative to the shift, (code - shift / step) mod 2^16, is the 16-bit quantized offset
// of the corner from the shift, which the encoder made fit in [0, 2^16).
MR_DEVICE float compact_decode_uv(mr_int shift, mr_uint code, mr_uint period_log2, float step) {
  const mr_uint relative = (code - ((mr_uint)shift << (16u - period_log2))) & 0xffffu;
  return (float)shift + (float)relative * step;
}

// A unit normal from its 16-bit octahedral code (8 bits of u in the low byte, v in the
// high; Cigolle et al., JCGT 2014).
MR_DEVICE mr_float3 compact_decode_normal(mr_uint code) {
  const float u = (float)(code & 0xffu) * (2.0f / 255.0f) - 1.0f;
  const float v = (float)(code >> 8) * (2.0f / 255.0f) - 1.0f;
  mr_float3 n = MR_FLOAT3(u, v, 1.0f - mr_fabs(u) - mr_fabs(v));
  if (n.z < 0.0f) {
    n.x = (1.0f - mr_fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    n.y = (1.0f - mr_fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
  }
  return normalize3(n);
}

// A child's box plane from its parent's decoded planes `lo`..`hi` and its 8-bit code, q /
// 255 of the way across. A lower plane is measured from `lo` and an upper one from `hi`,
// so the plane a child most often shares with its parent comes out exact without a
// select: code 0 of a lower plane is `lo` (lo + (hi - lo) * 0) and code 255 of an upper
// plane is `hi`. The traversal's 4-wide decode (render/compact_accel.cpp) does the same
// arithmetic lane for lane; the encoder checks every plane against it.
MR_DEVICE float compact_dequantize_lower(float lo, float hi, mr_uint q) {
  return lo + (hi - lo) * ((float)q * (1.0f / 255.0f));
}
MR_DEVICE float compact_dequantize_upper(float lo, float hi, mr_uint q) {
  return hi + (lo - hi) * ((float)(255u - q) * (1.0f / 255.0f));
}
MR_DEVICE float compact_dequantize_plane(float lo, float hi, mr_uint q, bool upper) {
  return upper ? compact_dequantize_upper(lo, hi, q) : compact_dequantize_lower(lo, hi, q);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_COMPACT_H
