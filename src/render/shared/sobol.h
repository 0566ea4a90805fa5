// The path tracers' sample values (CPU and OpenCL, one definition): a shuffled, scrambled
// Sobol sequence per pixel, after Burley, "Practical Hash-based Owen Scrambling" (JCGT
// 9(4), 2020, §4-5). Sample `sample` of a pixel is point `sample` of that pixel's
// sequence, so a pixel's first N samples are evenly spread (stratified) in every
// dimension and in every pair of dimensions a 2D value is drawn from, where independent
// random numbers clump: the noise of N samples falls faster than 1/N. Like rng.h, every
// value is a pure function of (pixel, sample, frame, view, seed, dimension), so the image
// does not depend on who rendered which pixel.
//
// Each dimension (1D value or 2D pair) takes the first two Sobol dimensions (a (0,2)
// sequence) at an index shuffled by a nested uniform scramble of the index, and scrambles
// the values the same way, with seeds hashed from the pixel's key and the dimension: the
// dimensions are thus independent of one another ("padding"), and each value is uniform
// on [0, 1) on its own, so estimates stay unbiased whatever dimensions a path uses.
// Written in render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_SOBOL_H
#define MULTIRAY_RENDER_SHARED_SOBOL_H

#ifdef __cplusplus
#include "render/shared/rng.h"
#endif

MR_NAMESPACE_BEGIN

// Dimensions a path uses: the pixel jitter, then per bounce a fixed block (so bounce d's
// values always come from the same dimensions, whatever the earlier bounces took).
#define MR_SOBOL_CAMERA_DIMS 1u
#define MR_SOBOL_BOUNCE_DIMS 5u  // light choice, light 2D, lobe, BSDF 2D, Russian roulette

MR_CONSTEXPR mr_uint reverse_bits32(mr_uint x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

// A seeded permutation of 32-bit words in which each bit is flipped depending only on the
// bits below it (multiplying by an even constant carries upwards only): Laine and Karras'
// hash with the constants Burley tuned. Applied between two bit reversals it flips each
// bit of a fraction depending only on the bits above it: a nested uniform (Owen) scramble.
MR_CONSTEXPR mr_uint sobol_lk_hash(mr_uint x, mr_uint seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

MR_CONSTEXPR mr_uint owen_scramble(mr_uint x, mr_uint seed) {
  return reverse_bits32(sobol_lk_hash(reverse_bits32(x), seed));
}

// The second Sobol dimension of point `i` as a 32-bit fraction (the first is
// reverse_bits32(i)): its direction numbers are the rows of Pascal's triangle mod 2.
MR_CONSTEXPR mr_uint sobol_second(mr_uint i) {
  mr_uint v = 0x80000000u, r = 0;
  for (; i != 0u; i >>= 1, v ^= v >> 1)
    if ((i & 1u) != 0u) r ^= v;
  return r;
}

// A 32-bit fraction as a float in [0, 1): its top 24 bits, never rounded up to 1.
MR_CONSTEXPR float sobol_float(mr_uint x) { return (float)(x >> 8) * 5.9604644775390625e-8f; }

typedef struct {
  mr_ulong key;   // the pixel's (with frame, view and seed)
  mr_uint index;  // the sample's number in its pixel
  mr_uint dim;    // the next dimension to draw
} SampleStream;

// Sample `sample` of `pixel` (the linear pixel index in its view, or a sample's key).
MR_CONSTEXPR SampleStream sample_stream_for_path(mr_uint pixel, mr_uint sample, mr_uint frame,
                                                 mr_uint view, mr_ulong seed) {
  const mr_ulong k1 =
      mix64((((mr_ulong)view << 32) | frame) ^ mix64(seed + MR_U64(0x9e3779b97f4a7c15)));
  SampleStream s = {mix64((((mr_ulong)pixel << 32) | MR_U64(0x5a17)) ^ k1), sample, 0u};
  return s;
}

// The point of dimension s->dim (advanced by one): its two coordinates as fractions.
MR_CONSTEXPR void sample_fractions(SampleStream* s, mr_uint* x, mr_uint* y) {
  const mr_ulong h = mix64(s->key + (mr_ulong)(s->dim + 1u) * MR_U64(0xd1342543de82ef95));
  const mr_ulong h2 = mix64(h);
  const mr_uint i = owen_scramble(s->index, (mr_uint)h);
  *x = owen_scramble(reverse_bits32(i), (mr_uint)(h >> 32));
  *y = owen_scramble(sobol_second(i), (mr_uint)h2);
  ++s->dim;
}

MR_DEVICE float sample_1d(SampleStream* s) {
  mr_uint x = 0, y = 0;
  sample_fractions(s, &x, &y);
  return sobol_float(x);
}

// Two values drawn together (stratified as a pair).
MR_DEVICE mr_float2 sample_2d(SampleStream* s) {
  mr_uint x = 0, y = 0;
  sample_fractions(s, &x, &y);
  return MR_FLOAT2(sobol_float(x), sobol_float(y));
}

// Positions the stream at the first dimension of bounce `depth` (0: the camera ray's hit).
MR_DEVICE void sample_stream_at_bounce(SampleStream* s, int depth) {
  s->dim = MR_SOBOL_CAMERA_DIMS + (mr_uint)depth * MR_SOBOL_BOUNCE_DIMS;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SOBOL_H
