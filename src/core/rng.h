// Counter-based random numbers. A path's stream is a pure function of
// (pixel, sample, frame, view), so the image does not depend on which thread or device
// rendered which pixel: the strongest invariant multiray has (see DESIGN.md).
#pragma once

#include <cstdint>

namespace multiray {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a cheap, well-mixed 64-bit hash.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// PCG32 (O'Neill 2014), seeded from the path's key. 2^64 period per stream is far more
// than a path consumes.
class Rng {
 public:
  // `pixel` is the linear pixel index in its view; `seed` lets tests draw independent
  // images of the same scene.
  static Rng for_path(uint32_t pixel, uint32_t sample, uint32_t frame, uint32_t view,
                      uint64_t seed = 0) {
    const uint64_t k1 =
        mix64((uint64_t(view) << 32 | frame) ^ mix64(seed + 0x9e3779b97f4a7c15ull));
    const uint64_t k2 = mix64((uint64_t(pixel) << 32 | sample) ^ k1);
    return Rng(k2, k1);
  }

  Rng(uint64_t state, uint64_t stream) : inc_((stream << 1u) | 1u) {
    state_ = 0;
    next_u32();
    state_ += state;
    next_u32();
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }

  // Uniform in [0, 1): 24 random bits, so the result is never rounded up to 1.
  float next() { return float(next_u32() >> 8) * 0x1p-24f; }

 private:
  uint64_t state_;
  uint64_t inc_;
};

}  // namespace multiray
