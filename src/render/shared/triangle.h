// The ray/triangle test, written once for the CPU's compact BVH and compact kd-tree
// (render/compact_accel.cpp, compact_kdtree.cpp) and the OpenCL traversals
// (kernels/traverse.cl), in render/shared/language.h's dialect. Embree's own test is not
// this one; these are the structures multiray traverses itself.
#ifndef MULTIRAY_RENDER_SHARED_TRIANGLE_H
#define MULTIRAY_RENDER_SHARED_TRIANGLE_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

// e1 = v1 - v0 from e1n = v0 - v1, as each side computed it before the test was shared:
// 0 - e1n in C++, -e1n in OpenCL C. They differ only in the sign of a zero component, which
// can reach the result only through a barycentric of exactly zero; kept so that neither
// backend's images change.
#ifdef MR_OPENCL_C
#define MR_EDGE_FROM_NEGATED(e1n) (-(e1n))
#else
#define MR_EDGE_FROM_NEGATED(e1n) (::multiray::Vec3(0.0f) - (e1n))
#endif

MR_NAMESPACE_BEGIN

// Moller-Trumbore on the triangle with corner v0 and edges e1n = v0 - v1 (Embree's e1)
// and e2 = v2 - v0. For a hit at distance t in (tmin, tmax) returns true with *t and the
// barycentrics *u (of v1) and *v (of v2); the caller decides (cut-outs) whether to keep it.
// Points up to a few ulps outside the triangle may be accepted (see compact_kdtree.cpp).
MR_DEVICE bool intersect_triangle(mr_float3 org, mr_float3 dir, float tmin, float tmax,
                                  mr_float3 v0, mr_float3 e1n, mr_float3 e2, float* t, float* u,
                                  float* v) {
  const mr_float3 e1 = MR_EDGE_FROM_NEGATED(e1n);
  const mr_float3 p = cross3(dir, e2);
  const float det = dot3(e1, p);
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const mr_float3 s = org - v0;
  const float uu = dot3(s, p) * inv;
  if (uu < 0.0f || uu > 1.0f) return false;
  const mr_float3 q = cross3(s, e1);
  const float vv = dot3(dir, q) * inv;
  if (vv < 0.0f || uu + vv > 1.0f) return false;
  const float tt = dot3(e2, q) * inv;
  if (!(tt > tmin && tt < tmax)) return false;
  *t = tt;
  *u = uu;
  *v = vv;
  return true;
}

// The geometric normal of that triangle as Embree reports it (unnormalised, zero signs
// included): e2 x e1n.
MR_DEVICE mr_float3 triangle_normal(mr_float3 e1n, mr_float3 e2) { return cross3(e2, e1n); }

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_TRIANGLE_H
