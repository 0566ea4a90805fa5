// Linear-RGB float images and their files. A Framebuffer holds one view; pixels are
// written by exactly one device per frame (partitions are disjoint), so no locking.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace multiray {

struct Framebuffer {
  int width = 0, height = 0;
  std::vector<Vec3> pixels;  // row-major, y = 0 at the top

  Framebuffer() = default;
  Framebuffer(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h)) {}
  Vec3& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const Vec3& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

// FNV-1a (64 bit) over the pixels' float bits, continuing from `seed`: a fingerprint for
// checking that two renders are bit-identical (chain views by passing the previous hash).
uint64_t image_hash(const Framebuffer& fb, uint64_t seed = 0xcbf29ce484222325ull);

// sRGB-encoded 8-bit RGB after clamping; `exposure` multiplies radiance first.
std::vector<uint8_t> to_srgb8(const Framebuffer& fb, float exposure = 1.0f);

// All `views` (same size) tiled in one image, `columns` per row, row-major from the top
// left: the "quilt" light-field displays take.
Framebuffer make_quilt(const std::vector<Framebuffer>& views, int columns);

// Writers throw InputError naming the path when the file cannot be written.
void write_png(const std::string& path, const Framebuffer& fb, float exposure = 1.0f);
void write_png_rgb8(const std::string& path, int width, int height,
                    const std::vector<uint8_t>& rgb);
void write_exr(const std::string& path, const Framebuffer& fb);

}  // namespace multiray
