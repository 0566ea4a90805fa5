// Counter-based random numbers, one definition for the CPU's kernels (render/rng.h wraps
// it in the Rng class) and the OpenCL programs. A path's stream is a pure function of
// (pixel, sample, frame, view, seed), so the image does not depend on which thread or
// device rendered which pixel: the strongest invariant multiray has (see DESIGN.md), and
// the reason the OpenCL images draw exactly the CPU's numbers for every sample.
// Written in render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_RNG_H
#define MULTIRAY_RENDER_SHARED_RNG_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a cheap, well-mixed 64-bit hash.
MR_CONSTEXPR mr_ulong mix64(mr_ulong z) {
  z = (z ^ (z >> 30)) * MR_U64(0xbf58476d1ce4e5b9);
  z = (z ^ (z >> 27)) * MR_U64(0x94d049bb133111eb);
  return z ^ (z >> 31);
}

// PCG32 (O'Neill 2014): a 64-bit state and an odd stream increment. 2^64 period per
// stream is far more than a path consumes.
typedef struct {
  mr_ulong state;
  mr_ulong inc;
} RngState;

// The next 32 random bits; advances *r.
MR_CONSTEXPR mr_uint rng_u32(RngState* r) {
  const mr_ulong old = r->state;
  r->state = old * MR_U64(6364136223846793005) + r->inc;
  const mr_uint xorshifted = (mr_uint)(((old >> 18) ^ old) >> 27);
  const mr_uint rot = (mr_uint)(old >> 59);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

// Uniform in [0, 1): 24 random bits times 2^-24, so the result is never rounded up to 1.
MR_DEVICE float rng_next(RngState* r) { return (float)(rng_u32(r) >> 8) * 5.9604644775390625e-8f; }

// The stream of `stream` started at `state` (PCG32's seeding).
MR_CONSTEXPR RngState rng_seeded(mr_ulong state, mr_ulong stream) {
  RngState r = {0, (stream << 1) | 1u};
  rng_u32(&r);
  r.state += state;
  rng_u32(&r);
  return r;
}

// The stream of one camera path: `pixel` is the linear pixel index in its view (or a
// sample's key), `seed` lets tests draw independent images of the same scene.
MR_CONSTEXPR RngState rng_for_path(mr_uint pixel, mr_uint sample, mr_uint frame, mr_uint view,
                                   mr_ulong seed) {
  const mr_ulong k1 =
      mix64((((mr_ulong)view << 32) | frame) ^ mix64(seed + MR_U64(0x9e3779b97f4a7c15)));
  const mr_ulong k2 = mix64((((mr_ulong)pixel << 32) | sample) ^ k1);
  return rng_seeded(k2, k1);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_RNG_H
