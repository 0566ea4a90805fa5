// A ray, a hit and the hit triangle's shading record as every backend's traversal and the
// integrator (path.h) exchange them, in render/shared/language.h's dialect: Embree's
// queries on the CPU (render/accel.h) and the BVH walks (bvh_walk.h) fill the same Hit.
#ifndef MULTIRAY_RENDER_SHARED_RAY_H
#define MULTIRAY_RENDER_SHARED_RAY_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

typedef struct Ray {
  mr_float3 org, dir;
  float tmin MR_DEFAULT(0.0f);
  float tmax MR_DEFAULT(INFINITY);
} Ray;

typedef struct Hit {
  float t MR_DEFAULT(INFINITY);
  mr_uint prim MR_DEFAULT(0u);  // triangle index in the Scene
  float u MR_DEFAULT(0.0f);     // barycentrics of vertices 1 and 2
  float v MR_DEFAULT(0.0f);
  mr_float3 ng;  // unnormalised, Embree's Ng = cross(v2 - v0, v0 - v1)
} Hit;

// What the integrator reads of a triangle (scene_shading, surface.h): corner normals and
// uvs, and the material. The CPU stores one a triangle, a cache line each
// (render/shading_data.h's TriangleShading); the kernels fill one from StoredShading.
typedef struct MR_ALIGN_CPU(64) ShadingRecord {
  mr_float3 normal[3];
  mr_float2 uv[3];
  mr_uint material MR_DEFAULT(0u);
} ShadingRecord;

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_RAY_H
