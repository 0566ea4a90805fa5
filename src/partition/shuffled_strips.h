// Shuffled strips, after van Antwerpen, Seibert & Keller, "A Simple Load-Balancing Scheme
// with High Scaling Efficiency" (Ray Tracing Gems, 2019, ch. 24).
//
// Each view's pixels, in scanline order, are cut into 2^b strips of consecutive pixels.
// The strip order is permuted by reversing the bits of the strip index, which spreads
// any run of consecutive shuffled positions evenly over the image; device i then takes
// round(w_i·2^b) consecutive shuffled positions. So every device samples the whole view
// (its cost tracks the view's average cost) while its share stays a plain count.
#pragma once

#include <cstdint>
#include <vector>

#include "partition/rect.h"

namespace multiray::balance {

// The strip count for a view of `pixels` pixels: the largest b for which strips have at
// least `min_pixels` pixels, so strips hold min_pixels to 2·min_pixels pixels (floor/ceil
// of pixels/2^b); 1 gives Leria et al.'s rule (the most strips, 2^19 at 1280x720, about
// 1.8 px each). Views under 2·min_pixels pixels get b = 0: a single strip.
int strip_bits_for(int64_t pixels, int64_t min_pixels = 128);

// `value`'s lowest `bits` bits in reverse order (bits in 0..31; higher bits are dropped).
uint32_t bit_reverse(uint32_t value, int bits);

// Pixels [begin, end) of strip `index` of 2^bits in a view of `pixels` pixels: strip k
// starts at floor(k·pixels/2^bits), so lengths differ by at most one.
void strip_range(int64_t pixels, int bits, int64_t index, int64_t& begin, int64_t& end);

// Per device, the WorkItems of its shuffled strips: for every view (in order), the strips
// at shuffled positions [s_i, s_i + c_i) where c = apportion(ratios, 2^bits) (so all
// strips are assigned and a ratio of 0 gets none). A strip that wraps rows becomes up to
// three rects. `bits` < 0 chooses strip_bits_for(width*height); an explicit value is
// clamped so that every strip has at least one pixel. Items of one device are listed
// view by view in shuffled order. Empty lists for an empty image.
std::vector<std::vector<WorkItem>> shuffled_strips(int width, int height, int views,
                                                   const std::vector<double>& ratios,
                                                   int bits = -1);

}  // namespace multiray::balance
