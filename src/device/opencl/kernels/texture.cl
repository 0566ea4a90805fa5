// Wrapped, bilinearly filtered 8-bit textures, as scene/scene.cpp's Texture: texel centres
// at half-integers, bytes decoded through the CPU's own tables (`luts`, 256 entries per
// TexelCoding in its order; alpha always through the linear one).

float3 decode_texel(uint p, const __global float* lut) {
  return (float3)(lut[p & 0xffu], lut[(p >> 8) & 0xffu], lut[(p >> 16) & 0xffu]);
}

// Texture::footprint: the top-left texel (*x0, *y0) of the bilinear footprint of `uv`,
// wrapped, its right and lower neighbours (*x1, *y1) and the weights (*tx, *ty).
void texture_footprint(const __global TexInfo* info, float2 uv, int* x0, int* y0, int* x1,
                       int* y1, float* tx, float* ty) {
  const int w = info->width, h = info->height;
  const float fx = (uv.x - floor(uv.x)) * (float)w - 0.5f;
  const float fy = (uv.y - floor(uv.y)) * (float)h - 0.5f;
  const float x0f = floor(fx), y0f = floor(fy);
  *tx = fx - x0f, *ty = fy - y0f;
  int x = (int)x0f, y = (int)y0f;
  x = x < 0 ? w - 1 : min(x, w - 1);
  y = y < 0 ? h - 1 : min(y, h - 1);
  *x0 = x, *y0 = y;
  *x1 = x + 1 < w ? x + 1 : 0, *y1 = y + 1 < h ? y + 1 : 0;
}

// Texture::sample: decoded RGB; 1 for an empty texture.
float3 sample_texture(const __global TexInfo* info, const __global uint* texels,
                      const __global float* luts, float2 uv) {
  if (info->width <= 0 || info->height <= 0) return (float3)(1.0f);
  int x0, y0, x1, y1;
  float tx, ty;
  texture_footprint(info, uv, &x0, &y0, &x1, &y1, &tx, &ty);
  const __global uint* row0 = texels + info->offset + (size_t)y0 * (size_t)info->width;
  const __global uint* row1 = texels + info->offset + (size_t)y1 * (size_t)info->width;
  const __global float* lut = luts + 256u * info->coding;
  return lerp3(lerp3(decode_texel(row0[x0], lut), decode_texel(row0[x1], lut), tx),
               lerp3(decode_texel(row1[x0], lut), decode_texel(row1[x1], lut), tx), ty);
}

// Texture::sample_alpha: the top byte, linear; 1 for an empty texture.
float sample_texture_alpha(const __global TexInfo* info, const __global uint* texels,
                           const __global float* luts, float2 uv) {
  if (info->width <= 0 || info->height <= 0) return 1.0f;
  int x0, y0, x1, y1;
  float tx, ty;
  texture_footprint(info, uv, &x0, &y0, &x1, &y1, &tx, &ty);
  const __global uint* row0 = texels + info->offset + (size_t)y0 * (size_t)info->width;
  const __global uint* row1 = texels + info->offset + (size_t)y1 * (size_t)info->width;
  const __global float* lin = luts + 256u;  // TexelCoding::linear
  const float top = lin[row0[x0] >> 24] * (1.0f - tx) + lin[row0[x1] >> 24] * tx;
  const float bottom = lin[row1[x0] >> 24] * (1.0f - tx) + lin[row1[x1] >> 24] * tx;
  return top * (1.0f - ty) + bottom * ty;
}

// A texture of the scene by index, through SceneData.
float3 scene_texture(const SceneData* sc, int index, float2 uv) {
  return sample_texture(&sc->textures[index], sc->texels, sc->texel_luts, uv);
}
