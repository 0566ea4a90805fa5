// The CPU kernels' random numbers: the C++ face of render/shared/rng.h, whose PCG32 streams
// (seeded from pixel, sample, frame, view and seed) the OpenCL programs draw too.
#pragma once

#include <cstdint>

#include "render/shared/rng.h"

namespace multiray {

class Rng {
 public:
  // `pixel` is the linear pixel index in its view; `seed` lets tests draw independent
  // images of the same scene.
  static Rng for_path(uint32_t pixel, uint32_t sample, uint32_t frame, uint32_t view,
                      uint64_t seed = 0) {
    return Rng(rng_for_path(pixel, sample, frame, view, seed));
  }

  // The PCG32 stream `stream` started at `state`.
  Rng(uint64_t state, uint64_t stream) : s_(rng_seeded(state, stream)) {}

  uint32_t next_u32() { return rng_u32(&s_); }
  // Uniform in [0, 1): 24 random bits, so the result is never rounded up to 1.
  float next() { return rng_next(&s_); }

 private:
  explicit Rng(RngState s) : s_(s) {}
  RngState s_;
};

}  // namespace multiray
