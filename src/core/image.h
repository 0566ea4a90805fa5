// Linear-RGB float images and their files. A Framebuffer holds one view; pixels are
// written by exactly one device per frame (partitions are disjoint), so no locking.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/feature_buffers.h"
#include "core/math.h"

namespace multiray {

struct Framebuffer {
  int width = 0, height = 0;
  std::vector<Vec3> pixels;  // row-major, y = 0 at the top
  // Coverage in [0, 1] per pixel, row-major, or empty: an RGBA layer whose `pixels` are
  // premultiplied by it (the shadow catcher's output, render/shadow_catcher.h).
  std::vector<float> alpha;
  // The path tracer's feature buffers (AOVs) of the same pixels, or empty: only when the
  // frame's RenderSettings::feature_buffers asked for them (core/feature_buffers.h).
  FeatureBuffers features;

  Framebuffer() = default;
  Framebuffer(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h)) {}
  Vec3& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const Vec3& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

// XXH3 (64 bit, xxHash) over the pixels' float bits, seeded with `seed`: a fingerprint for
// checking that two renders are bit-identical (chain views by passing the previous hash).
// The alpha channel, when there is one, is hashed after the pixels, seeded with theirs.
// (FNV-1a until 2026-12-04: byte by byte, 3.1-3.2 ms for a 640x360 frame, which the
// viewer paid twice a frame; XXH3 takes 0.16-0.18 ms, docs/benchmarks.md.)
uint64_t image_hash(const Framebuffer& fb, uint64_t seed = 0xcbf29ce484222325ull);

// How linear radiance becomes an 8-bit display value (PNG; EXR files stay linear).
enum class ToneCurve {
  Clamp,   // radiance clipped to [0, 1]: the default's images before tone mapping existed
  Filmic,  // tone_filmic(): highlights roll off instead of clipping
};
struct Display {
  float exposure_ev = 0.0f;  // stops: radiance is multiplied by 2^exposure_ev first
  ToneCurve tone = ToneCurve::Clamp;
};

// Exposure in stops as a factor on radiance: 2^ev.
float exposure_scale(float ev);
// The ACES filmic curve as fitted by Narkowicz ("ACES Filmic Tone Mapping Curve", 2015):
// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]. Applied per channel
// to linear radiance; monotone on [0, inf), 0 -> 0, reaches 1 at x ~ 7.24 (so about three
// stops above 1 stay distinguishable where clamping loses them). Negative and NaN give 0.
float tone_filmic(float x);
// Linear radiance -> linear display value in [0, 1] under `d` (exposure, then the curve).
float display_value(float radiance, const Display& d);

// sRGB-encoded 8-bit RGB of display_value() of every channel.
std::vector<uint8_t> to_srgb8(const Framebuffer& fb, const Display& d = {});

// All `views` (same size) tiled in one image, `columns` per row, row-major from the top
// left: the "quilt" light-field displays take.
Framebuffer make_quilt(const std::vector<Framebuffer>& views, int columns);

// Writers throw InputError naming the path when the file cannot be written.
void write_png(const std::string& path, const Framebuffer& fb, const Display& d = {});
void write_png_rgb8(const std::string& path, int width, int height,
                    const std::vector<uint8_t>& rgb);
// JPEG bytes of 8-bit RGB pixels at `quality` in [1, 100] (for streaming to a viewer).
std::string encode_jpeg(int width, int height, const std::vector<uint8_t>& rgb, int quality);
// Linear radiance as 32-bit float R, G, B channels (ZIP-compressed), bit for bit, and A
// when the image has alpha (premultiplied colour, as EXR's convention is).
void write_exr(const std::string& path, const Framebuffer& fb);
// The R, G, B channels of an EXR file as floats (any pixel type, any data window).
// Throws InputError naming the path when it cannot be read or is larger than 2^28 pixels.
Framebuffer read_exr(const std::string& path);

}  // namespace multiray
