// Surface scattering for the Material model of scene.h. All directions are in the local
// shading frame (normal = +z); `wo` points towards the viewer, `wi` towards the light.
//
// - Lambertian diffuse.
// - Rough conductor: GGX microfacets (Walter et al. 2007) with Smith shadowing, Schlick
//   Fresnel with F0 = base colour, visible-normal sampling (Heitz 2018).
// - Rough dielectric: GGX reflection/refraction chosen by exact Fresnel. It is only
//   sampled, never evaluated, so it takes no part in next-event estimation and MIS; paths
//   through it collect emission as after a specular bounce (still unbiased).
#pragma once

#include "core/math.h"
#include "scene/scene.h"

namespace multiray {

struct BsdfSample {
  Vec3 wi;
  Vec3 weight;            // f * |cos| / pdf
  float pdf = 0;          // solid-angle density; 0 when `specular`
  bool specular = false;  // not usable for MIS (dielectric or near-mirror)
};

class Bsdf {
 public:
  // `base_color`, `metallic` and `roughness` already include the texture lookups
  // (render/surface.h); `m` gives the rest (transmission, ior).
  Bsdf(const Material& m, Vec3 base_color, float metallic, float roughness);

  // True if eval()/pdf() are meaningful, i.e. next-event estimation may be used.
  bool has_diffuse_or_glossy() const { return !dielectric_; }
  // f(wo, wi) * |cos theta_i|.
  Vec3 eval(Vec3 wo, Vec3 wi) const;
  float pdf(Vec3 wo, Vec3 wi) const;
  // Returns false when the path should end (sample below the surface, TIR loss, ...).
  bool sample(Vec3 wo, float u_lobe, float u1, float u2, BsdfSample& out) const;

 private:
  Vec3 color_;
  float metallic_;
  float alpha_;
  float ior_;
  bool dielectric_;
};

}  // namespace multiray
