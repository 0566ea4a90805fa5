// The one dialect of the physics that C++ and OpenCL C share (pbrt-v4's PBRT_CPU_GPU,
// OSPRay's *Shared.h). Every header under render/shared/ is written in it, once, and
// compiled twice: by the C++ compiler as part of render/ (through ordinary #includes) and
// by the OpenCL C 1.2 compiler as part of the device's programs, which embed these headers
// as text ahead of their own .cl files (src/device/opencl/CMakeLists.txt), so an installed
// binary needs no file at run time and the kernel cache's key (the source) covers them.
//
// Rules for code in render/shared/ (the CPU's images must not change by a bit, and the
// OpenCL C must be standard 1.2, not what one driver tolerates):
// - Functions are MR_DEVICE (C++: inline in namespace multiray; OpenCL C: ordinary
//   program-scope functions) or MR_CONSTEXPR for pure integer arithmetic.
// - Types: float, mr_short, mr_ushort (arrays the host uploads), mr_int, mr_uint, mr_long,
//   mr_ulong (64-bit literals: MR_U64(0x...)); vectors
//   mr_float2 / mr_float3 (C++: core/math.h's Vec2 / Vec3; OpenCL C: float2 / float3),
//   built with MR_FLOAT2(x, y) / MR_FLOAT3(x, y, z), combined with + - * and the helpers
//   below; mr_float4 / mr_int4 only in blocks the host writes (16 bytes each, MR_XYZ
//   reads a float4's first three). Float literals carry `f`; no double anywhere.
// - The helpers dot3, cross3, normalize3, max3, lerp3, finite3 and the shading Frame
//   (frame_from_normal, to_local, to_world) are core/math.h's in C++ and written out in
//   the same order of operations for OpenCL C; load3 reads three floats of a record;
//   mr_fmax is std::max in C++ and fmax in OpenCL C (equal unless an argument is NaN,
//   which no caller passes).
// - mr_fabs, mr_pow, mr_atan2, mr_acos, mr_expm1, mr_exp, mr_clamp, mr_floor, mr_ceil,
//   mr_min_int and mr_max_int are std::abs, pow, atan2, acos, expm1, exp, clamp, floor,
//   ceil, min and max in C++ and the built-ins of the same names in OpenCL C (mr_isfinite
//   too, in conditions only: OpenCL C's returns an int): each side keeps the functions
//   it used before the code was shared (the two libraries' results may differ in the last
//   ulp; an image is bit-identical to itself on one backend, not across backends).
//   clamp_std (transfer.h) is std::clamp's definition on both sides. mr_float_as_uint and
//   mr_uint_as_float reinterpret a float's bits (as_uint, as_float in OpenCL C).
// - Pointers point to private memory (OpenCL C 1.2 has no generic address space), except
//   MR_GLOBAL ones (`__global` in OpenCL C, nothing in C++): tables the host uploads.
// - A shared header includes its shared dependencies only for C++ (#ifdef __cplusplus):
//   the programs embed each file once, in dependency order. Include guards, not #pragma
//   once: in a program the text is part of the main file.
#ifndef MULTIRAY_RENDER_SHARED_LANGUAGE_H
#define MULTIRAY_RENDER_SHARED_LANGUAGE_H

// OpenCL C 1.2 compilers define __OPENCL_C_VERSION__; __OPENCL_VERSION__ is the device's
// (PoCL defines it, a bare front end such as clang -x cl does not).
#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)

#define MR_OPENCL_C 1
// Contraction of a*b+c into fma is off: a fused and an unfused evaluation of the same
// pixel must never coexist (e.g. vectorised and scalar work-item loops), or images would
// depend on how the frame was split. (The C++ side is built for generic x86-64, whose
// instruction set has no fma to contract into; docs/testing.md.)
#pragma OPENCL FP_CONTRACT OFF

#define MR_DEVICE
#define MR_CONSTEXPR
#define MR_NAMESPACE_BEGIN
#define MR_NAMESPACE_END
#define MR_U64(x) x##UL
#define MR_DEFAULT(x)    // a member's default value, C++ only
#define MR_ALIGN_CPU(n)  // a record's alignment in the CPU's memory, C++ only

typedef uchar mr_uchar;
typedef short mr_short;
typedef ushort mr_ushort;
typedef int mr_int;
typedef uint mr_uint;
typedef ulong mr_ulong;
typedef long mr_long;
typedef float2 mr_float2;
typedef float3 mr_float3;
typedef float4 mr_float4;
typedef int4 mr_int4;

#define MR_PI 3.14159265358979323846f
#define MR_INV_PI (1.0f / MR_PI)
#define MR_GLOBAL __global
#define MR_FLOAT2(x, y) ((float2)((x), (y)))
#define MR_FLOAT3(x, y, z) ((float3)((x), (y), (z)))
#define MR_XYZ(v) ((v).xyz)
#define mr_sqrt sqrt
#define mr_cos cos
#define mr_sin sin
#define mr_fmax fmax
#define mr_fabs fabs
#define mr_pow pow
#define mr_atan2 atan2
#define mr_acos acos
#define mr_expm1 expm1
#define mr_exp exp
#define mr_isfinite isfinite
#define mr_clamp clamp
#define mr_floor floor
#define mr_ceil ceil
#define mr_min_int min
#define mr_max_int max
#define mr_float_as_uint as_uint
#define mr_uint_as_float as_float

// As core/math.h's dot, cross and normalize, operation for operation (not the built-ins,
// whose order of operations is the driver's).
float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
float3 cross3(float3 a, float3 b) {
  return (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
float3 normalize3(float3 a) {
  const float l = sqrt(dot3(a, a));
  return l > 0.0f ? a * (1.0f / l) : (float3)(0.0f, 0.0f, 1.0f);
}
float3 load3(const __global float* p) { return (float3)(p[0], p[1], p[2]); }
float max3(float3 a) { return fmax(a.x, fmax(a.y, a.z)); }
float3 lerp3(float3 a, float3 b, float t) { return a * (1.0f - t) + b * t; }
bool finite3(float3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
// core/math.h's safe_inverse: 1 / d, components under 1e-30 in magnitude taken as
// +-1e-30 (sign kept), so a slab test never computes 0 * inf.
float3 safe_inverse(float3 d) {
  const float3 tiny = copysign((float3)(1e-30f), d);
  return 1.0f / select(d, tiny, isless(fabs(d), (float3)(1e-30f)));
}

// Orthonormal basis around unit `n` (Duff et al. 2017), as core/math.h's Frame.
typedef struct {
  float3 t, b, n;
} Frame;
Frame frame_from_normal(float3 n) {
  const float sign = copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float bb = n.x * n.y * a;
  Frame f;
  f.t = (float3)(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  f.b = (float3)(bb, sign + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}
float3 to_local(const Frame* f, float3 v) {
  return (float3)(dot3(v, f->t), dot3(v, f->b), dot3(v, f->n));
}
float3 to_world(const Frame* f, float3 v) { return f->t * v.x + f->b * v.y + f->n * v.z; }

#else  // C++

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/math.h"

#define MR_DEVICE inline
#define MR_CONSTEXPR constexpr
#define MR_NAMESPACE_BEGIN namespace multiray {
#define MR_NAMESPACE_END }
#define MR_U64(x) x##ull
#define MR_DEFAULT(x) = x
#define MR_ALIGN_CPU(n) alignas(n)

namespace multiray {
typedef uint8_t mr_uchar;
typedef int16_t mr_short;
typedef uint16_t mr_ushort;
typedef int32_t mr_int;
typedef uint32_t mr_uint;
typedef uint64_t mr_ulong;
typedef int64_t mr_long;
typedef Vec2 mr_float2;
typedef Vec3 mr_float3;
// OpenCL C's float4 and int4 as the host writes them into parameter blocks.
struct alignas(16) mr_float4 {
  float x, y, z, w;
};
struct alignas(16) mr_int4 {
  int32_t x, y, z, w;
};
static_assert(sizeof(mr_float4) == 16 && sizeof(mr_int4) == 16);

inline float dot3(Vec3 a, Vec3 b) { return dot(a, b); }
inline Vec3 cross3(Vec3 a, Vec3 b) { return cross(a, b); }
inline Vec3 normalize3(Vec3 a) { return normalize(a); }
inline Vec3 load3(const float* p) { return Vec3(p[0], p[1], p[2]); }
inline uint32_t mr_float_as_uint(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}
inline float mr_uint_as_float(uint32_t b) {
  float f;
  std::memcpy(&f, &b, sizeof f);
  return f;
}
inline float max3(Vec3 a) { return max_component(a); }
inline Vec3 lerp3(Vec3 a, Vec3 b, float t) { return lerp(a, b, t); }
inline bool finite3(Vec3 a) { return is_finite(a); }
inline Frame frame_from_normal(Vec3 n) { return Frame::from_normal(n); }
inline Vec3 to_local(const Frame* f, Vec3 v) { return f->to_local(v); }
inline Vec3 to_world(const Frame* f, Vec3 v) { return f->to_world(v); }
}  // namespace multiray

#define MR_PI ::multiray::kPi
#define MR_INV_PI ::multiray::kInvPi
#define MR_GLOBAL
#define MR_FLOAT2(x, y) (::multiray::Vec2{(x), (y)})
#define MR_FLOAT3(x, y, z) (::multiray::Vec3((x), (y), (z)))
#define MR_XYZ(v) (::multiray::Vec3((v).x, (v).y, (v).z))
#define mr_sqrt std::sqrt
#define mr_cos std::cos
#define mr_sin std::sin
#define mr_fmax std::max
#define mr_fabs std::abs
#define mr_pow std::pow
#define mr_atan2 std::atan2
#define mr_acos std::acos
#define mr_expm1 std::expm1
#define mr_exp std::exp
#define mr_isfinite std::isfinite
#define mr_clamp std::clamp
#define mr_floor std::floor
#define mr_ceil std::ceil
#define mr_min_int std::min
#define mr_max_int std::max

#endif

#endif  // MULTIRAY_RENDER_SHARED_LANGUAGE_H
