#include "partition/shuffled_strips.h"

#include <algorithm>
#include <cstddef>

#include "partition/apportion.h"
#include "partition/scanline.h"

namespace multiray::balance {

namespace {
// 2^24 strips is far beyond any real view (2^31 pixels at 128 px per strip) and keeps
// strip index × pixels inside 64 bits.
constexpr int kMaxBits = 24;
}  // namespace

int strip_bits_for(int64_t pixels, int64_t min_pixels) {
  int bits = 0;
  while (bits < kMaxBits && (pixels >> (bits + 1)) >= std::max<int64_t>(min_pixels, 1)) ++bits;
  return bits;
}

uint32_t bit_reverse(uint32_t value, int bits) {
  uint32_t out = 0;
  for (int i = 0; i < bits; ++i) {
    out = (out << 1) | (value & 1u);
    value >>= 1;
  }
  return out;
}

void strip_range(int64_t pixels, int bits, int64_t index, int64_t& begin, int64_t& end) {
  begin = (index * pixels) >> bits;
  end = ((index + 1) * pixels) >> bits;
}

std::vector<std::vector<WorkItem>> shuffled_strips(int width, int height, int views,
                                                   const std::vector<double>& ratios, int bits) {
  std::vector<std::vector<WorkItem>> out(ratios.size());
  const int64_t pixels = int64_t(std::max(width, 0)) * std::max(height, 0);
  if (pixels == 0 || views <= 0 || ratios.empty()) return out;

  if (bits < 0) bits = strip_bits_for(pixels);
  // Every strip must hold a pixel: 2^bits <= pixels.
  while (bits > 0 && (int64_t(1) << bits) > pixels) --bits;
  bits = std::min(bits, kMaxBits);
  const int64_t strips = int64_t(1) << bits;

  const std::vector<int64_t> counts = apportion(ratios, strips);
  for (int view = 0; view < views; ++view) {
    int64_t position = 0;
    for (size_t device = 0; device < counts.size(); ++device) {
      for (int64_t k = 0; k < counts[device]; ++k, ++position) {
        int64_t begin = 0, end = 0;
        strip_range(pixels, bits, bit_reverse(uint32_t(position), bits), begin, end);
        append_scanline_rects(width, begin, end, view, out[device]);
      }
    }
  }
  return out;
}

}  // namespace multiray::balance
