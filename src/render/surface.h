// A Material evaluated at one surface point: each factor times its texture (scene.h).
// The one place the CPU kernels read material textures; kernels/surface.cl mirrors it
// for OpenCL, in the same order of operations.
#pragma once

#include "core/math.h"
#include "render/shading_data.h"
#include "scene/scene.h"

namespace multiray {

struct SurfacePoint {
  Vec3 base_color;
  float metallic = 0;
  float roughness = 1;
  Vec3 ns;  // shading normal after the normal map
};

// Emitted radiance of `m` at texture coordinate `uv` (zero if it does not emit).
Vec3 emission_at(const Scene& scene, const Material& m, Vec2 uv);

// Scattering parameters of `m` at `uv`. `ns` is the interpolated shading normal (unit, on
// the side of `ng`); a normal map tilts it in the frame of `tangent` (null: no map
// applied), and is ignored where the result would face away from `ng`. `base_footprint`,
// if given, is the base colour texture's footprint at `uv` (the same lookup, done once).
SurfacePoint surface_at(const Scene& scene, const Material& m, Vec2 uv, Vec3 ns, Vec3 ng,
                        const TriangleTangent* tangent,
                        const Texture::Footprint* base_footprint = nullptr);

// Coverage of `m` at `uv` in [0, 1]: opacity times the base colour texture's alpha.
float alpha_at(const Scene& scene, const Material& m, Vec2 uv);

// Whether a ray passes through the point of `m` at `uv`: `mask` compares the coverage
// with the cutoff, `blend` compares it with `u` (uniform in [0, 1), fixed per ray so
// that every device makes the same decision). Always false for opaque materials.
bool passes_through(const Scene& scene, const Material& m, Vec2 uv, float u);

}  // namespace multiray
