// Wrapped, bilinearly filtered 8-bit sRGB textures, as scene/scene.cpp's Texture: texel
// centres at half-integers, bytes decoded through the CPU's own table (`lut`).

float3 decode_texel(uint p, const __global float* lut) {
  return (float3)(lut[p & 0xffu], lut[(p >> 8) & 0xffu], lut[(p >> 16) & 0xffu]);
}

float3 sample_texture(const __global TexInfo* info, const __global uint* texels,
                      const __global float* lut, float2 uv) {
  const int w = info->width, h = info->height;
  if (w <= 0 || h <= 0) return (float3)(1.0f);
  const float fx = (uv.x - floor(uv.x)) * (float)w - 0.5f;
  const float fy = (uv.y - floor(uv.y)) * (float)h - 0.5f;
  const float x0f = floor(fx), y0f = floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  int x0 = (int)x0f, y0 = (int)y0f;
  x0 = x0 < 0 ? w - 1 : min(x0, w - 1);
  y0 = y0 < 0 ? h - 1 : min(y0, h - 1);
  const int x1 = x0 + 1 < w ? x0 + 1 : 0, y1 = y0 + 1 < h ? y0 + 1 : 0;
  const __global uint* row0 = texels + info->offset + (size_t)y0 * (size_t)w;
  const __global uint* row1 = texels + info->offset + (size_t)y1 * (size_t)w;
  return lerp3(lerp3(decode_texel(row0[x0], lut), decode_texel(row0[x1], lut), tx),
               lerp3(decode_texel(row1[x0], lut), decode_texel(row1[x1], lut), tx), ty);
}
