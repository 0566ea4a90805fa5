// Fixed-width bit packing for the compact mesh's per-triangle arrays (faces, material ids,
// uv shifts): every value of an array takes as many bits as the array's largest value
// needs, so a face of a mesh of 40,000 vertices takes 3 x 16 bits instead of 3 x 32, and a
// scene of one material stores no material ids at all. The width is fixed per array, so
// value i is found without decoding its neighbours (the random access Seo, Park & Ihm's
// faces keep). Reading is render/shared/compact.h's compact_read_bits, shared with the
// OpenCL kernel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/shared/compact.h"

namespace multiray {

// Bits needed to hold every value in 0..max_value: 0 for 0, 32 for values of 2^31 and up.
inline uint32_t bits_for(uint32_t max_value) {
  uint32_t bits = 0;
  while (bits < 32 && (max_value >> bits) != 0) ++bits;
  return bits;
}

struct PackedUints {
  uint32_t width = 0;           // bits per value, 0..32
  size_t count = 0;             // values
  std::vector<uint32_t> words;  // ceil(count * width / 32) words, least significant bit first

  size_t size() const { return count; }
  bool empty() const { return count == 0; }
  size_t bytes() const { return words.size() * sizeof(uint32_t); }
  uint32_t operator[](size_t i) const { return compact_read_bits(words.data(), i, width); }
  std::vector<uint32_t> unpacked() const {
    std::vector<uint32_t> out(count);
    for (size_t i = 0; i < count; ++i) out[i] = (*this)[i];
    return out;
  }

  // `values` in the width of their largest value.
  static PackedUints pack(const std::vector<uint32_t>& values) {
    uint32_t largest = 0;
    for (uint32_t v : values) largest = v > largest ? v : largest;
    return pack(values, bits_for(largest));
  }
  // `values` in `width` bits each; every value must fit.
  static PackedUints pack(const std::vector<uint32_t>& values, uint32_t width) {
    PackedUints p;
    p.width = width;
    p.count = values.size();
    p.words.assign((uint64_t(p.count) * width + 31) / 32, 0u);
    for (size_t i = 0; i < p.count && width > 0; ++i) {
      const uint64_t bit = uint64_t(i) * width;
      const uint32_t shift = uint32_t(bit & 31);
      p.words[bit >> 5] |= values[i] << shift;
      if (shift + width > 32) p.words[(bit >> 5) + 1] |= values[i] >> (32 - shift);
    }
    return p;
  }
};

}  // namespace multiray
