// Wrapped, bilinearly filtered 8-bit textures (scene/scene.h's Texture holds them):
// texel centres at half-integers, bytes decoded through the CPU's own tables (one per
// TexelCoding; alpha always through the linear one). Written once for every backend in
// render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_TEXTURE_H
#define MULTIRAY_RENDER_SHARED_TEXTURE_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// A texture as the integrator reads it: texels row-major, v = 0 at the top row,
// R | G<<8 | B<<16 | A<<24; `lut` the 256 linear values of its coding and `alpha_lut`
// the linear coding's. Made by each backend's scene_texture() (its SceneData).
typedef struct {
  const MR_GLOBAL mr_uint* texels;
  const MR_GLOBAL float* lut;
  const MR_GLOBAL float* alpha_lut;
  mr_int width, height;
} TextureView;

// Where the bilinear filter at one uv reads: the texel offsets of its two rows
// (y * width) and columns, wrapped into the texture, and its weights towards the second
// of each. The CPU's path tracer works it out once a hit to prefetch the texels.
typedef struct {
  mr_uint row0, row1, x0, x1;
  float tx, ty;
} TexFootprint;

// The footprint at `uv` of a texture that is not empty. fx lies in [-0.5, width - 0.5),
// so the left neighbour is in [-1, width - 1] and wrapping needs a compare, not a modulo.
MR_DEVICE TexFootprint texture_footprint(const TextureView* t, mr_float2 uv) {
  const float fx = (uv.x - mr_floor(uv.x)) * (float)t->width - 0.5f;
  const float fy = (uv.y - mr_floor(uv.y)) * (float)t->height - 0.5f;
  const float x0f = mr_floor(fx), y0f = mr_floor(fy);
  TexFootprint f;
  f.tx = fx - x0f;
  f.ty = fy - y0f;
  mr_int x0 = (mr_int)x0f, y0 = (mr_int)y0f;
  x0 = x0 < 0 ? t->width - 1 : mr_min_int(x0, t->width - 1);
  y0 = y0 < 0 ? t->height - 1 : mr_min_int(y0, t->height - 1);
  const mr_int x1 = x0 + 1 < t->width ? x0 + 1 : 0, y1 = y0 + 1 < t->height ? y0 + 1 : 0;
  f.x0 = (mr_uint)x0;
  f.x1 = (mr_uint)x1;
  f.row0 = (mr_uint)y0 * (mr_uint)t->width;
  f.row1 = (mr_uint)y1 * (mr_uint)t->width;
  return f;
}

MR_DEVICE mr_float3 decode_texel(mr_uint p, const MR_GLOBAL float* lut) {
  return MR_FLOAT3(lut[p & 0xffu], lut[(p >> 8) & 0xffu], lut[(p >> 16) & 0xffu]);
}

// Decoded RGB at a footprint.
MR_DEVICE mr_float3 texture_sample_at(const TextureView* t, const TexFootprint* f) {
  const MR_GLOBAL mr_uint* row0 = t->texels + f->row0;
  const MR_GLOBAL mr_uint* row1 = t->texels + f->row1;
  return lerp3(lerp3(decode_texel(row0[f->x0], t->lut), decode_texel(row0[f->x1], t->lut), f->tx),
               lerp3(decode_texel(row1[f->x0], t->lut), decode_texel(row1[f->x1], t->lut), f->tx),
               f->ty);
}

MR_DEVICE bool texture_empty(const TextureView* t) { return t->width <= 0 || t->height <= 0; }

// Decoded RGB at `uv`; 1 for an empty texture.
MR_DEVICE mr_float3 texture_sample(const TextureView* t, mr_float2 uv) {
  if (texture_empty(t)) return MR_FLOAT3(1.0f, 1.0f, 1.0f);
  const TexFootprint f = texture_footprint(t, uv);
  return texture_sample_at(t, &f);
}

// Alpha at `uv` (the top byte, linear); 1 for an empty texture.
MR_DEVICE float texture_sample_alpha(const TextureView* t, mr_float2 uv) {
  if (texture_empty(t)) return 1.0f;
  const TexFootprint f = texture_footprint(t, uv);
  const MR_GLOBAL mr_uint* row0 = t->texels + f.row0;
  const MR_GLOBAL mr_uint* row1 = t->texels + f.row1;
  const MR_GLOBAL float* a = t->alpha_lut;
  const float top = a[row0[f.x0] >> 24] * (1.0f - f.tx) + a[row0[f.x1] >> 24] * f.tx;
  const float bottom = a[row1[f.x0] >> 24] * (1.0f - f.tx) + a[row1[f.x1] >> 24] * f.tx;
  return top * (1.0f - f.ty) + bottom * f.ty;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_TEXTURE_H
