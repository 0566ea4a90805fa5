// The CPU's face of render/shared/bsdf.h, the BSDF the OpenCL path tracer evaluates too:
// Lambertian diffuse, the GGX conductor and the rough dielectric of scene.h's Material.
// All directions are in the local shading frame (normal = +z); `wo` points towards the
// viewer, `wi` towards the light.
#pragma once

#include "core/math.h"
#include "render/shared/bsdf.h"
#include "scene/scene.h"

namespace multiray {

// The material's index of refraction as the BSDF uses it (1.5 unless the material gives
// one above 1), and whether the material is the dielectric. No texture changes either, so
// the OpenCL device decides them once per material (device/gpu_scene/scene_buffers.cpp).
inline float material_ior(const Material& m) { return m.ior > 1.0f ? m.ior : 1.5f; }
inline bool material_is_dielectric(const Material& m) { return m.transmission > 0.5f; }

class Bsdf {
 public:
  // `base_color`, `metallic` and `roughness` already include the texture lookups
  // (render/surface.h); `m` gives the rest (transmission, ior).
  Bsdf(const Material& m, Vec3 base_color, float metallic, float roughness)
      : p_(bsdf_params(base_color, metallic, roughness, material_ior(m),
                       material_is_dielectric(m))) {}

  // True if eval()/pdf() are meaningful, i.e. next-event estimation may be used.
  bool has_diffuse_or_glossy() const { return !p_.dielectric; }
  // Whether sample() reads its `u_lobe` (bsdf_chooses_lobe).
  bool chooses_lobe() const { return bsdf_chooses_lobe(&p_); }
  // f(wo, wi) * |cos theta_i|.
  Vec3 eval(Vec3 wo, Vec3 wi) const { return bsdf_eval(&p_, wo, wi); }
  float pdf(Vec3 wo, Vec3 wi) const { return bsdf_pdf(&p_, wo, wi); }
  // Returns false when the path should end (sample below the surface, TIR loss, ...).
  bool sample(Vec3 wo, float u_lobe, float u1, float u2, BsdfSample& out) const {
    return bsdf_sample(&p_, wo, u_lobe, u1, u2, &out);
  }

 private:
  BsdfParams p_;
};

}  // namespace multiray
