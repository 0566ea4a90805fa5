// Augmented reality's last step: a rendered RGBA layer (premultiplied colour, the shadow
// catcher's output, render/shadow_catcher.h) over a real image, and the real images
// themselves (--background: a photograph, or one frame of a phone video per frame).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"

namespace multiray {

// rgb + (1 - alpha) * background per pixel (Porter & Duff's "over" with premultiplied
// colour). `layer` must have an alpha channel and background's size. Where alpha is 0 and
// rgb 0 the background is returned bit for bit.
Framebuffer composite_over(const Framebuffer& layer, const Framebuffer& background);

// 8-bit sRGB RGBA of `layer` with straight (not premultiplied) colour, as PNG files hold
// it: colour = rgb / alpha under `d`, alpha = alpha. Fully transparent pixels are black.
std::vector<uint8_t> to_srgba8(const Framebuffer& layer, const Display& d = {});
// PNG bytes of 8-bit RGBA pixels (for files and for streaming to a browser).
std::string encode_png_rgba(int width, int height, const std::vector<uint8_t>& rgba);
// The layer as an RGBA PNG (to_srgba8), written atomically; InputError naming the path.
void write_png_rgba(const std::string& path, const Framebuffer& layer, const Display& d = {});

// An image file as linear RGB: PNG, JPEG, BMP, TGA (sRGB decoded) or OpenEXR (linear).
// InputError naming the path for a missing, unreadable or undecodable file, or one larger
// than 2^28 pixels.
Framebuffer read_image_linear(const std::string& path);

// Bytes held at once while frame() brings an image of w x h pixels with `channels`
// channels (0: an EXR, read straight into floats) to width x height: the decoder's
// pixels, the linear image and, when the sizes differ, the resampled one.
uint64_t background_decode_bytes(int64_t w, int64_t h, int channels, int width, int height);

// The real images of a run: one file for every frame, or a numbered sequence whose run of
// '#' is the frame number zero-padded to its length (bg_####.png: bg_0000.png, ...), as
// -o patterns are written. Each is brought to the output's size: as it is, or by bilinear
// resampling when its aspect ratio is the output's within 1%; otherwise refused.
class BackgroundImages {
 public:
  // Checks that the images of frames [0, frames) exist and have a usable size (their
  // headers only, before anything renders). InputError "--background ..." otherwise.
  BackgroundImages(std::string spec, int width, int height, int frames);
  // Frame `frame`'s image at the output size, linear RGB.
  Framebuffer frame(int frame) const;
  // The file of frame `frame`.
  std::string path(int frame) const;

  // The frame whose image takes the most memory while frame() reads it (from the headers
  // the constructor read): its file, size in pixels and background_decode_bytes(). Nothing
  // is kept between frames, so this is what --max-memory must allow on top of the run.
  struct Largest {
    std::string path;
    int64_t width = 0, height = 0;
    uint64_t bytes = 0;
  };
  const Largest& largest() const { return largest_; }

 private:
  std::string spec_;
  size_t hashes_at_ = std::string::npos, hashes_ = 0;  // the run of '#'
  int width_, height_;
  Largest largest_;
};

}  // namespace multiray
