// The random numbers of core/rng.h, bit for bit: a path's PCG32 stream is seeded from
// (pixel, sample, frame, view, seed) exactly as Rng::for_path does, so the OpenCL image
// draws the same numbers as the CPU's for every sample.

// SplitMix64 finaliser.
ulong mix64(ulong z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9UL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebUL;
  return z ^ (z >> 31);
}

typedef struct {
  ulong state;
  ulong inc;
} Rng;

uint rng_u32(Rng* r) {
  const ulong old = r->state;
  r->state = old * 6364136223846793005UL + r->inc;
  const uint xorshifted = (uint)(((old >> 18) ^ old) >> 27);
  const uint rot = (uint)(old >> 59);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

// Uniform in [0, 1) from the top 24 bits.
float rng_next(Rng* r) { return (float)(rng_u32(r) >> 8) * 5.9604644775390625e-8f; }

Rng rng_for_path(uint pixel, uint sample, uint frame, uint view, ulong seed) {
  const ulong k1 = mix64((((ulong)view << 32) | frame) ^ mix64(seed + 0x9e3779b97f4a7c15UL));
  const ulong k2 = mix64((((ulong)pixel << 32) | sample) ^ k1);
  Rng r;
  r.inc = (k1 << 1) | 1UL;
  r.state = 0;
  rng_u32(&r);
  r.state += k2;
  rng_u32(&r);
  return r;
}
