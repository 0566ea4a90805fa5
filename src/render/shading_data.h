// Everything shading needs about a triangle, packed into one 64-byte cache line.
//
// Why: Embree keeps its own copy of the geometry, so a hit's shading used to fetch the
// index triple, then three positions, three normals and three uvs from separate arrays:
// up to ten cache misses per hit on large scenes, which profiling showed dominated the
// path tracer's own time. One aligned record per triangle makes it one miss.
#pragma once

#include <vector>

#include "core/math.h"
#include "render/shared/ray.h"
#include "scene/scene.h"

namespace multiray {

// Per-corner shading normals (the face normal when the scene has none), per-corner
// texture coordinates (0 when the scene has none) and the material.
typedef ShadingRecord TriangleShading;
static_assert(sizeof(TriangleShading) == 64, "one cache line per triangle");

std::vector<TriangleShading> build_shading_data(const Scene& scene);

// The record of triangle `prim` decoded from a compact scene, with build_shading_data()'s
// rules (face normal when the scene has no normals, uv 0 when it has no uvs).
struct CompactScene;
TriangleShading decode_shading(const CompactScene& c, uint32_t prim);

// Per-triangle tangent frame for normal mapping: `u` is dp/du (unit), `sign` is +1 or -1
// so that cross(n, u) * sign points along -dp/dv, glTF's "+y of the normal map" (its v
// axis points down the image). u = 0 where the triangle's uvs have no area (the map is
// then not applied). One per triangle rather than MikkTSpace's per-vertex tangents: exact
// for planar uv charts, an approximation across curved ones (see docs/scenes.md).
struct TriangleTangent {
  Vec3 u{0.0f};
  float sign = 1.0f;
};

// Empty when no material has a normal texture (the common case costs nothing).
std::vector<TriangleTangent> build_tangents(const Scene& scene);

}  // namespace multiray
