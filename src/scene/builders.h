// Scenes built in code: the default scene and analytic test scenes with known answers.
#pragma once

#include "scene/scene.h"

namespace multiray {

// Appends geometry to a scene; every call returns the index of the first new triangle.
// Every builder adds vertex normals (face normals for quads and boxes, the sphere's own
// for spheres), so shapes can be mixed in one scene. Quads are given counter-clockwise as
// seen from the side their normal points to.
uint32_t add_quad(Scene& s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, uint32_t material);
// Axis-aligned box rotated by `yaw_deg` about +y through its centre, outward faces.
uint32_t add_box(Scene& s, Vec3 center, Vec3 half_size, float yaw_deg, uint32_t material);
// UV sphere with `rings` x `segments` quads; `inward` flips the winding and normals.
uint32_t add_sphere(Scene& s, Vec3 center, float radius, int rings, int segments, bool inward,
                    uint32_t material);
uint32_t add_material(Scene& s, Material m);

// The built-in default scene: a Cornell box with an area light, after the classic Cornell
// box (red left wall, green right wall, two white blocks), sized like McGuire's
// CornellBox-Original (2 units wide, light Ke = (17, 12, 4)). Includes one camera.
Scene make_cornell_box();

// White furnace: a closed sphere whose inside has diffuse albedo `albedo` and emits `le`;
// every path sees radiance le / (1 - albedo). Camera at the centre.
Scene make_furnace_sphere(float albedo, float le);

// A large diffuse square (albedo `albedo`, facing +y) under a constant environment of
// radiance `env`, seen from above. With bounces >= 1, the plane's outgoing radiance is
// albedo * env (the sky hemisphere is unoccluded), the sky shows env.
Scene make_lit_plane(float albedo, float env);

// A diffuse sphere (radius 1 at the origin, albedo `albedo`, a UV sphere of `rings` x
// `segments` quads) lit only by a small square light (side kLitSphereLightSide) facing it
// from kLitSphereLightDistance away along kLitSphereLightDir, in a black environment; the
// camera looks at it from +z. `smooth`: with the sphere's vertex normals, else without
// (flat facets). The light's radiance makes the irradiance of a surface facing it 1 at the
// centre, so with one bounce a point with normal n has radiance albedo / pi * cos(n, light)
// (up to the light's finite size and distance, ~1e-3 relative).
Scene make_lit_sphere(float albedo, int rings, int segments, bool smooth);
constexpr float kLitSphereLightDistance = 20.0f;
constexpr float kLitSphereLightSide = 0.5f;
inline Vec3 lit_sphere_light_dir() { return normalize(Vec3(1.0f, 1.5f, 2.0f)); }

}  // namespace multiray
