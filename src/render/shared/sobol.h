// The path tracers' sample values (CPU and OpenCL, one definition): a shuffled, scrambled
// Sobol sequence per pixel, after Burley, "Practical Hash-based Owen Scrambling" (JCGT
// 9(4), 2020, §4-5). Sample `sample` of a pixel is point `sample` of that pixel's
// sequence, so a pixel's first N samples are evenly spread (stratified) in every
// dimension and in every pair of dimensions a 2D value is drawn from, where independent
// random numbers clump: the variance of a pixel's mean of N samples falls faster than
// 1/N. Like rng.h, every value is a pure function of (pixel, sample, frame, view, seed,
// dimension), so the image does not depend on who rendered which pixel.
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
#define MR_SOBOL_BSDF_OFFSET 2u  // where the BSDF's lobe and 2D value start in that block

// Bit k of `x` moved to bit 31 - k, written twice with equal results on every input (all
// 2^32 compared once; SobolBits.* compares them on every byte value and the OpenCL values
// with the CPU's). C++ swaps halves, bytes, nibbles, pairs and bits. OpenCL C reverses
// each byte by multiplications ("Bit Twiddling Hacks", the byte in 7 operations without
// 64 bits): clang recognises the swaps as the intrinsic llvm.bitreverse, which backends
// lower but Oclgrind, which interprets the IR, cannot run ("Undefined external function:
// llvm.bitreverse.i32"); products hide the bit moves from that recognition
// (OpenClStrict.NoProgramCallsAnIntrinsicAnInterpreterLacks).
MR_CONSTEXPR mr_uint reverse_bits8_by_products(mr_uint b) {
  return (((b * 0x0802u & 0x22110u) | (b * 0x8020u & 0x88440u)) * 0x10101u >> 16) & 0xffu;
}
MR_CONSTEXPR mr_uint reverse_bits32_by_products(mr_uint x) {
  return reverse_bits8_by_products(x >> 24) | (reverse_bits8_by_products((x >> 16) & 0xffu) << 8) |
         (reverse_bits8_by_products((x >> 8) & 0xffu) << 16) |
         (reverse_bits8_by_products(x & 0xffu) << 24);
}
#ifdef MR_OPENCL_C
MR_CONSTEXPR mr_uint reverse_bits32(mr_uint x) { return reverse_bits32_by_products(x); }
#else
MR_CONSTEXPR mr_uint reverse_bits32(mr_uint x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}
#endif

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

// The second Sobol dimension of point `i`, bit-reversed (bit k holds the fraction's
// 2^-(k+1) digit; the first dimension reversed is `i` itself). Its generator matrix is
// Pascal's triangle mod 2: digit k is the parity of the index bits j with j & k == k
// (Lucas), a superset sum over the bit positions, done for all 32 in five steps.
MR_CONSTEXPR mr_uint sobol_second_reversed(mr_uint i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  return i ^ ((i >> 16) & 0x0000ffffu);
}

// A 32-bit fraction as a float in [0, 1): its top 24 bits, never rounded up to 1.
MR_CONSTEXPR float sobol_float(mr_uint x) { return (float)(x >> 8) * 5.9604644775390625e-8f; }

typedef struct {
  mr_ulong key;            // the pixel's (with frame, view and seed)
  mr_uint index_reversed;  // the sample's number in its pixel, bit-reversed
  mr_uint dim;             // the next dimension to draw
} SampleStream;

// Sample `sample` of `pixel` (the linear pixel index in its view, or a sample's key).
MR_CONSTEXPR SampleStream sample_stream_for_path(mr_uint pixel, mr_uint sample, mr_uint frame,
                                                 mr_uint view, mr_ulong seed) {
  const mr_ulong k1 =
      mix64((((mr_ulong)view << 32) | frame) ^ mix64(seed + MR_U64(0x9e3779b97f4a7c15)));
  SampleStream s = {mix64((((mr_ulong)pixel << 32) | MR_U64(0x5a17)) ^ k1), reverse_bits32(sample),
                    0u};
  return s;
}

// Dimension s->dim's hash, and its shuffled index (the sample's number under a nested
// uniform scramble); advances s->dim. The scrambles of a reversed fraction are done on
// the reversed word (where the hash flips each bit by the bits below it) and reversed
// once at the end, so each value costs one bit reversal.
MR_CONSTEXPR mr_uint sample_dimension(SampleStream* s, mr_ulong* h) {
  *h = mix64(s->key + (mr_ulong)(s->dim + 1u) * MR_U64(0xd1342543de82ef95));
  ++s->dim;
  return reverse_bits32(sobol_lk_hash(s->index_reversed, (mr_uint)*h));
}

MR_DEVICE float sample_1d(SampleStream* s) {
  mr_ulong h = 0;
  const mr_uint i = sample_dimension(s, &h);
  return sobol_float(reverse_bits32(sobol_lk_hash(i, (mr_uint)(h >> 32))));
}

// Two values drawn together (stratified as a pair: a (0,2) sequence).
MR_DEVICE mr_float2 sample_2d(SampleStream* s) {
  mr_ulong h = 0;
  const mr_uint i = sample_dimension(s, &h);
  const mr_uint x = reverse_bits32(sobol_lk_hash(i, (mr_uint)(h >> 32)));
  const mr_uint y = reverse_bits32(sobol_lk_hash(sobol_second_reversed(i), (mr_uint)mix64(h)));
  return MR_FLOAT2(sobol_float(x), sobol_float(y));
}

// Positions the stream at the first dimension of bounce `depth` (0: the camera ray's hit).
MR_DEVICE void sample_stream_at_bounce(SampleStream* s, int depth) {
  s->dim = MR_SOBOL_CAMERA_DIMS + (mr_uint)depth * MR_SOBOL_BOUNCE_DIMS;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_SOBOL_H
