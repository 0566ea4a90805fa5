// A Material of scene/scene.h at one surface point, for the CPU's traversal (the cut-out
// filters of render/accel.cpp and compact_accel.cpp) and the light sampler's power
// estimate. The integrator evaluates materials through render/shared/surface.h instead,
// over MaterialRecords; both read textures with render/shared/texture.h.
#pragma once

#include "core/math.h"
#include "scene/scene.h"

namespace multiray {

// Emitted radiance of `m` at texture coordinate `uv` (zero if it does not emit).
Vec3 emission_at(const Scene& scene, const Material& m, Vec2 uv);

// Coverage of `m` at `uv` in [0, 1]: opacity times the base colour texture's alpha.
float alpha_at(const Scene& scene, const Material& m, Vec2 uv);

// Whether a ray passes through the point of `m` at `uv`: `mask` compares the coverage
// with the cutoff, `blend` compares it with `u` (uniform in [0, 1), fixed per ray so
// that every device makes the same decision). Always false for opaque materials.
bool passes_through(const Scene& scene, const Material& m, Vec2 uv, float u);

}  // namespace multiray
