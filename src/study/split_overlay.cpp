#include "study/split_overlay.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/core.h>

// stb_easy_font: a bitmap font as quads, all static functions (Debian's libstb-dev).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace multiray::study {

namespace {

constexpr uint8_t kPalette[8][3] = {{230, 159, 0},   {86, 180, 233}, {0, 158, 115},
                                    {240, 228, 66},  {0, 114, 178},  {213, 94, 0},
                                    {204, 121, 167}, {153, 153, 153}};
constexpr float kTint = 0.4f;   // how much of the device's colour shows over the frame
constexpr float kEdge = 0.75f;  // and on the outline of each piece

void put(Rgb8Image& im, int x, int y, const uint8_t c[3], float a = 1) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  uint8_t* p = &im.rgb[(size_t(y) * size_t(im.width) + size_t(x)) * 3];
  for (int k = 0; k < 3; ++k) p[k] = uint8_t(float(p[k]) * (1 - a) + float(c[k]) * a + 0.5f);
}

void fill(Rgb8Image& im, int x0, int y0, int x1, int y1, const uint8_t c[3]) {
  for (int y = std::max(y0, 0); y < std::min(y1, im.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, im.width); ++x) put(im, x, y, c);
}

// Text at (x, y) (top left), each font pixel drawn as scale x scale image pixels.
void text(Rgb8Image& im, int x, int y, const std::string& s, int scale, const uint8_t c[3]) {
  std::vector<char> chars(s.begin(), s.end());
  chars.push_back('\0');
  std::vector<char> quads(chars.size() * 300 + 1024);  // ~270 bytes a character (stb)
  const int n = stb_easy_font_print(0, 0, chars.data(), nullptr, quads.data(), int(quads.size()));
  struct Vertex {
    float x, y, z;
    uint8_t colour[4];
  };
  const auto* v = reinterpret_cast<const Vertex*>(quads.data());
  for (int q = 0; q < n; ++q) {  // each quad is an axis-aligned box: corners 0 and 2
    const Vertex& a = v[4 * q];
    const Vertex& b = v[4 * q + 2];
    fill(im, x + int(a.x) * scale, y + int(a.y) * scale, x + int(b.x) * scale,
         y + int(b.y) * scale, c);
  }
}

Rect clip(const Rect& r, int w, int h) {
  return Rect{std::clamp(r.x0, 0, w), std::clamp(r.y0, 0, h), std::clamp(r.x1, 0, w),
              std::clamp(r.y1, 0, h)};
}

}  // namespace

void device_colour(size_t i, uint8_t out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = kPalette[i % 8][k];
}

Rgb8Image split_overlay(const Rgb8Image& frame, const std::vector<OverlayDevice>& devices,
                        const std::string& title) {
  if (frame.width <= 0 || frame.height <= 0 ||
      frame.rgb.size() != size_t(frame.width) * size_t(frame.height) * 3)
    throw std::invalid_argument("split_overlay: the frame's pixels do not match its size");
  const int scale = frame.width >= 600 ? 2 : 1;
  const int row = 12 * scale;  // stb_easy_font's line height, 12 font pixels
  const int pad = 4 * scale;
  Rgb8Image out;
  out.width = frame.width;
  out.height = frame.height + pad * 2 + row * int(devices.size() + 1);
  out.rgb.assign(size_t(out.width) * size_t(out.height) * 3, 24);  // the legend's dark grey
  std::copy(frame.rgb.begin(), frame.rgb.end(), out.rgb.begin());
  for (size_t d = 0; d < devices.size(); ++d) {
    uint8_t c[3];
    device_colour(d, c);
    for (const Rect& raw : devices[d].rects) {
      const Rect r = clip(raw, frame.width, frame.height);
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const bool edge = x == r.x0 || y == r.y0 || x == r.x1 - 1 || y == r.y1 - 1;
          put(out, x, y, c, edge ? kEdge : kTint);
        }
    }
  }
  const uint8_t white[3] = {235, 235, 235};
  int y = frame.height + pad;
  text(out, pad, y, title, scale, white);
  for (size_t d = 0; d < devices.size(); ++d) {
    y += row;
    uint8_t c[3];
    device_colour(d, c);
    fill(out, pad, y, pad + 8 * scale, y + 7 * scale, c);
    const OverlayDevice& dev = devices[d];
    const std::string line = dev.left_out ? fmt::format("{}  left out", dev.name)
                                          : fmt::format("{}  {:.1f}% of samples  {:.0f} ms busy",
                                                        dev.name, 100 * dev.share, dev.busy_ms);
    text(out, pad + 12 * scale, y, line, scale, white);
  }
  return out;
}

}  // namespace multiray::study
