// Surface scattering for the Material model of scene/scene.h, written once for the CPU's
// path tracer (render/bsdf.h's Bsdf is its C++ face) and the OpenCL one, in
// render/shared/language.h's dialect. All directions are in the local shading frame
// (normal = +z); `wo` points towards the viewer, `wi` towards the light.
//
// - Lambertian diffuse.
// - Rough conductor: GGX microfacets (Walter et al. 2007) with Smith shadowing, Schlick
//   Fresnel with F0 = base colour, visible-normal sampling (Heitz 2018).
// - Rough dielectric: GGX reflection/refraction chosen by exact Fresnel. It is only
//   sampled, never evaluated, so it takes no part in next-event estimation and MIS; paths
//   through it collect emission as after a specular bounce (still unbiased).
#ifndef MULTIRAY_RENDER_SHARED_BSDF_H
#define MULTIRAY_RENDER_SHARED_BSDF_H

#ifdef __cplusplus
#include "render/shared/language.h"
#include "render/shared/sampling.h"
#endif

MR_NAMESPACE_BEGIN

// A material at one surface point, textures already applied; made by bsdf_params.
typedef struct {
  mr_float3 color;  // base colour times texture
  float metallic;   // in [0, 1]
  float alpha;      // GGX roughness (perceptual roughness squared), >= 1e-3
  float ior;        // > 1; only for the dielectric
  bool dielectric;
} BsdfParams;

typedef struct {
  mr_float3 wi;
  mr_float3 weight;  // f * |cos| / pdf
  float pdf;         // solid-angle density; 0 when `specular`
  bool specular;     // not usable for MIS (the dielectric)
} BsdfSample;

// `metallic` and `roughness` (perceptual) as textured, clamped here; `ior` and `dielectric`
// as the material gives them (render/bsdf.h's material_ior, material_is_dielectric).
MR_DEVICE BsdfParams bsdf_params(mr_float3 color, float metallic, float roughness, float ior,
                                 bool dielectric) {
  BsdfParams b;
  b.color = color;
  b.metallic = mr_clamp(metallic, 0.0f, 1.0f);
  b.alpha = mr_fmax(roughness * roughness, 1e-3f);
  b.ior = ior;
  b.dielectric = dielectric;
  return b;
}

// GGX normal distribution D(m) for a microfacet normal m.
MR_DEVICE float ggx_d(mr_float3 m, float a) {
  if (m.z <= 0.0f) return 0.0f;
  const float a2 = a * a, c2 = m.z * m.z;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (MR_PI * d * d);
}

// Smith masking G1 for GGX.
MR_DEVICE float ggx_g1(mr_float3 v, float a) {
  const float c2 = v.z * v.z;
  if (c2 <= 0.0f) return 0.0f;
  const float tan2 = mr_fmax(0.0f, 1.0f - c2) / c2;
  return 2.0f / (1.0f + mr_sqrt(1.0f + a * a * tan2));
}

// Visible-normal sampling for GGX (Heitz 2018, JCGT 7(4)); `wo` must have wo.z > 0.
MR_DEVICE mr_float3 sample_ggx_vndf(mr_float3 wo, float a, float u1, float u2) {
  const mr_float3 vh = normalize3(MR_FLOAT3(a * wo.x, a * wo.y, wo.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const mr_float3 t1 = lensq > 0.0f ? MR_FLOAT3(-vh.y, vh.x, 0.0f) * (1.0f / mr_sqrt(lensq))
                                    : MR_FLOAT3(1.0f, 0.0f, 0.0f);
  const mr_float3 t2 = cross3(vh, t1);
  const float r = mr_sqrt(u1);
  const mr_float2 cs = cos_sin_turns(u2);
  const float p1 = r * cs.x;
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * mr_sqrt(mr_fmax(0.0f, 1.0f - p1 * p1)) + s * r * cs.y;
  const mr_float3 nh = t1 * p1 + t2 * p2 + vh * mr_sqrt(mr_fmax(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize3(MR_FLOAT3(a * nh.x, a * nh.y, mr_fmax(1e-6f, nh.z)));
}

MR_DEVICE mr_float3 schlick(mr_float3 f0, float cos_theta) {
  const float m = mr_pow(mr_clamp(1.0f - cos_theta, 0.0f, 1.0f), 5.0f);
  return f0 + (MR_FLOAT3(1.0f, 1.0f, 1.0f) - f0) * m;
}

// Unpolarised Fresnel reflectance of a dielectric; `eta` = n_transmitted / n_incident;
// returns 1 on total internal reflection.
MR_DEVICE float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = mr_sqrt(1.0f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// `w` mirrored about `m`.
MR_DEVICE mr_float3 reflect3(mr_float3 w, mr_float3 m) { return m * (2.0f * dot3(w, m)) - w; }

// f(wo, wi) * |cos theta_i|; 0 for the dielectric.
MR_DEVICE mr_float3 bsdf_eval(const BsdfParams* b, mr_float3 wo, mr_float3 wi) {
  if (b->dielectric || wo.z <= 0.0f || wi.z <= 0.0f) return MR_FLOAT3(0.0f, 0.0f, 0.0f);
  mr_float3 f = b->color * (MR_INV_PI * wi.z * (1.0f - b->metallic));
  if (b->metallic > 0.0f) {
    const mr_float3 m = normalize3(wo + wi);
    const float g = ggx_g1(wo, b->alpha) * ggx_g1(wi, b->alpha);
    f += schlick(b->color, dot3(wi, m)) * (b->metallic * ggx_d(m, b->alpha) * g / (4.0f * wo.z));
  }
  return f;
}

// Solid-angle density with which bsdf_sample returns `wi`; 0 for the dielectric.
MR_DEVICE float bsdf_pdf(const BsdfParams* b, mr_float3 wo, mr_float3 wi) {
  if (b->dielectric || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  float p = (1.0f - b->metallic) * wi.z * MR_INV_PI;
  if (b->metallic > 0.0f) {
    const mr_float3 m = normalize3(wo + wi);
    // VNDF density of m, times the reflection Jacobian 1 / (4 wo.m).
    p += b->metallic * ggx_g1(wo, b->alpha) * ggx_d(m, b->alpha) / (4.0f * wo.z);
  }
  return p;
}

// Whether bsdf_sample reads `u_lobe`: only between two lobes (a dielectric's reflection
// and refraction, a partly metallic surface's glossy and diffuse lobes). A metallic of 0
// or 1 decides alone, since u_lobe lies in [0, 1).
MR_DEVICE bool bsdf_chooses_lobe(const BsdfParams* b) {
  return b->dielectric || (b->metallic > 0.0f && b->metallic < 1.0f);
}

// Samples `out` with the lobe chosen by `u_lobe` and the direction by (u1, u2). Returns
// false when the path should end (sample below the surface, lost to total internal
// reflection, ...).
MR_DEVICE bool bsdf_sample(const BsdfParams* b, mr_float3 wo, float u_lobe, float u1, float u2,
                           BsdfSample* out) {
  if (b->dielectric) {
    // wo.z < 0 means the path arrives from inside the object.
    const bool inside = wo.z < 0.0f;
    const mr_float3 w = inside ? -wo : wo;
    const float eta = inside ? 1.0f / b->ior : b->ior;
    const mr_float3 m = sample_ggx_vndf(w, b->alpha, u1, u2);
    const float cos_o = dot3(w, m);
    const float fr = fresnel_dielectric(cos_o, eta);
    mr_float3 wi;
    float scale = 1.0f;
    if (u_lobe < fr) {
      wi = reflect3(w, m);
      if (wi.z <= 0.0f) return false;
    } else {
      const float sin2_t = (1.0f - cos_o * cos_o) / (eta * eta);
      const float cos_t = mr_sqrt(mr_fmax(0.0f, 1.0f - sin2_t));
      wi = m * (cos_o / eta - cos_t) - w * (1.0f / eta);
      if (wi.z >= 0.0f) return false;
      scale = 1.0f / (eta * eta);  // radiance is compressed entering a denser medium
    }
    // With VNDF sampling and choosing the lobe by Fresnel, f*cos/pdf = G1(wi).
    const float g = scale * ggx_g1(MR_FLOAT3(wi.x, wi.y, mr_fabs(wi.z)), b->alpha);
    out->weight = MR_FLOAT3(g, g, g);
    out->wi = inside ? -wi : wi;
    out->pdf = 0.0f;
    out->specular = true;
    return true;
  }
  if (wo.z <= 0.0f) return false;
  if (u_lobe < b->metallic) {
    out->wi = reflect3(wo, sample_ggx_vndf(wo, b->alpha, u1, u2));
  } else {
    out->wi = sample_cosine_hemisphere(u1, u2);
  }
  if (out->wi.z <= 0.0f) return false;
  out->pdf = bsdf_pdf(b, wo, out->wi);
  if (!(out->pdf > 0.0f)) return false;
  out->weight = bsdf_eval(b, wo, out->wi) * (1.0f / out->pdf);
  out->specular = false;
  return true;
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_BSDF_H
