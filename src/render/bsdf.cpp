#include "render/bsdf.h"

#include <cmath>

#include "render/shared/sampling.h"

namespace multiray {

namespace {

// GGX normal distribution D(m) for a microfacet normal m (local frame).
float ggx_d(Vec3 m, float a) {
  if (m.z <= 0) return 0;
  const float a2 = a * a, c2 = m.z * m.z;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Smith masking G1 for GGX.
float ggx_g1(Vec3 v, float a) {
  const float c2 = v.z * v.z;
  if (c2 <= 0) return 0;
  const float tan2 = std::max(0.0f, 1.0f - c2) / c2;
  return 2.0f / (1.0f + std::sqrt(1.0f + a * a * tan2));
}

// Visible-normal sampling for GGX (Heitz 2018, JCGT 7(4)); `wo` must have wo.z > 0.
Vec3 sample_ggx_vndf(Vec3 wo, float a, float u1, float u2) {
  const Vec3 vh = normalize(Vec3(a * wo.x, a * wo.y, wo.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0 ? Vec3(-vh.y, vh.x, 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = cross(vh, t1);
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize(Vec3(a * nh.x, a * nh.y, std::max(1e-6f, nh.z)));
}

Vec3 schlick(Vec3 f0, float cos_theta) {
  const float m = std::pow(std::clamp(1.0f - cos_theta, 0.0f, 1.0f), 5.0f);
  return f0 + (Vec3(1.0f) - f0) * m;
}

// Unpolarised Fresnel reflectance of a dielectric; `eta` = n_transmitted / n_incident;
// returns 1 on total internal reflection.
float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

Vec3 reflect(Vec3 w, Vec3 m) { return m * (2.0f * dot(w, m)) - w; }

}  // namespace

Bsdf::Bsdf(const Material& m, Vec3 base_color, float metallic, float roughness)
    : color_(base_color),
      metallic_(std::clamp(metallic, 0.0f, 1.0f)),
      alpha_(std::max(roughness * roughness, 1e-3f)),
      ior_(m.ior > 1.0f ? m.ior : 1.5f),
      dielectric_(m.transmission > 0.5f) {}

Vec3 Bsdf::eval(Vec3 wo, Vec3 wi) const {
  if (dielectric_ || wo.z <= 0 || wi.z <= 0) return Vec3(0.0f);
  Vec3 f = color_ * (kInvPi * wi.z * (1.0f - metallic_));
  if (metallic_ > 0) {
    const Vec3 m = normalize(wo + wi);
    const float g = ggx_g1(wo, alpha_) * ggx_g1(wi, alpha_);
    f += schlick(color_, dot(wi, m)) * (metallic_ * ggx_d(m, alpha_) * g / (4.0f * wo.z));
  }
  return f;
}

float Bsdf::pdf(Vec3 wo, Vec3 wi) const {
  if (dielectric_ || wo.z <= 0 || wi.z <= 0) return 0;
  float p = (1.0f - metallic_) * wi.z * kInvPi;
  if (metallic_ > 0) {
    const Vec3 m = normalize(wo + wi);
    // VNDF density of m, times the reflection Jacobian 1 / (4 wo.m).
    p += metallic_ * ggx_g1(wo, alpha_) * ggx_d(m, alpha_) / (4.0f * wo.z);
  }
  return p;
}

bool Bsdf::sample(Vec3 wo, float u_lobe, float u1, float u2, BsdfSample& out) const {
  if (dielectric_) {
    // wo.z < 0 means the path arrives from inside the object.
    const bool inside = wo.z < 0;
    const Vec3 w = inside ? -wo : wo;
    const float eta = inside ? 1.0f / ior_ : ior_;
    const Vec3 m = sample_ggx_vndf(w, alpha_, u1, u2);
    const float cos_o = dot(w, m);
    const float fr = fresnel_dielectric(cos_o, eta);
    Vec3 wi;
    float scale = 1.0f;
    if (u_lobe < fr) {
      wi = reflect(w, m);
      if (wi.z <= 0) return false;
    } else {
      const float sin2_t = (1.0f - cos_o * cos_o) / (eta * eta);
      const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
      wi = m * (cos_o / eta - cos_t) - w / eta;
      if (wi.z >= 0) return false;
      scale = 1.0f / (eta * eta);  // radiance is compressed entering a denser medium
    }
    // With VNDF sampling and choosing the lobe by Fresnel, f*cos/pdf = G1(wi).
    out.weight = Vec3(scale * ggx_g1(Vec3(wi.x, wi.y, std::abs(wi.z)), alpha_));
    out.wi = inside ? -wi : wi;
    out.pdf = 0;
    out.specular = true;
    return true;
  }
  if (wo.z <= 0) return false;
  if (u_lobe < metallic_) {
    const Vec3 m = sample_ggx_vndf(wo, alpha_, u1, u2);
    out.wi = reflect(wo, m);
  } else {
    out.wi = sample_cosine_hemisphere(u1, u2);
  }
  if (out.wi.z <= 0) return false;
  out.pdf = pdf(wo, out.wi);
  if (!(out.pdf > 0)) return false;
  out.weight = eval(wo, out.wi) / out.pdf;
  out.specular = false;
  return true;
}

}  // namespace multiray
