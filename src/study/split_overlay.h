// A picture of how a frame was split between devices: the frame as written, each device's
// region tinted in its colour with the outline of every piece it rendered, and a legend
// under it (device, share of the frame's samples, busy time). Pure: 8-bit sRGB in, 8-bit
// sRGB out, no files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "util/rect.h"

namespace multiray::study {

struct OverlayDevice {
  std::string name;         // as the user gave it ("opencl:0:cores=1")
  std::vector<Rect> rects;  // the pieces it rendered, in pixels of the frame
  double share = 0;         // of the frame's samples, in [0, 1]
  double busy_ms = 0;       // its time at work in the frame
  bool left_out = false;    // rested this frame (took no part)
};

struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3, rows top to bottom
};

// The colour of device i (a colour-blind-safe palette, Okabe & Ito; repeats after 8).
void device_colour(size_t i, uint8_t out[3]);

// `frame` (width x height, rgb) with each device's pieces tinted and outlined, and a legend
// strip below it headed by `title`. Rects are clipped to the frame. Throws
// std::invalid_argument when rgb's size does not match.
Rgb8Image split_overlay(const Rgb8Image& frame, const std::vector<OverlayDevice>& devices,
                        const std::string& title);

}  // namespace multiray::study
