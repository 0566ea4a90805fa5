// The materials of render/bsdf.cpp, operation for operation: Lambertian diffuse, GGX
// conductor with visible-normal sampling, and the rough dielectric (sample only). All
// directions in the local shading frame (normal = +z); `wo` towards the viewer.

typedef struct {
  float3 color;  // base colour times texture
  float metallic, alpha, ior;
  bool dielectric;
} Bsdf;

typedef struct {
  float3 wi;
  float3 weight;  // f * |cos| / pdf
  float pdf;      // 0 when specular
  bool specular;
} BsdfSample;

// GGX normal distribution D(m).
float ggx_d(float3 m, float a) {
  if (m.z <= 0.0f) return 0.0f;
  const float a2 = a * a, c2 = m.z * m.z;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (PI * d * d);
}

// Smith masking G1.
float ggx_g1(float3 v, float a) {
  const float c2 = v.z * v.z;
  if (c2 <= 0.0f) return 0.0f;
  const float tan2 = fmax(0.0f, 1.0f - c2) / c2;
  return 2.0f / (1.0f + sqrt(1.0f + a * a * tan2));
}

// Visible-normal sampling (Heitz 2018); `wo.z` > 0.
float3 sample_ggx_vndf(float3 wo, float a, float u1, float u2) {
  const float3 vh = normalize3((float3)(a * wo.x, a * wo.y, wo.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const float3 t1 = lensq > 0.0f ? (float3)(-vh.y, vh.x, 0.0f) * (1.0f / sqrt(lensq))
                                 : (float3)(1.0f, 0.0f, 0.0f);
  const float3 t2 = cross3(vh, t1);
  const float r = sqrt(u1), phi = 2.0f * PI * u2;
  const float p1 = r * cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * r * sin(phi);
  const float3 nh = t1 * p1 + t2 * p2 + vh * sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize3((float3)(a * nh.x, a * nh.y, fmax(1e-6f, nh.z)));
}

float3 schlick(float3 f0, float cos_theta) {
  const float m = pow(clamp(1.0f - cos_theta, 0.0f, 1.0f), 5.0f);
  return f0 + ((float3)(1.0f) - f0) * m;
}

// Unpolarised Fresnel reflectance; `eta` = n_t / n_i; 1 on total internal reflection.
float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = sqrt(1.0f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

float3 reflect3(float3 w, float3 m) { return m * (2.0f * dot3(w, m)) - w; }

// f(wo, wi) * |cos theta_i|.
float3 bsdf_eval(const Bsdf* b, float3 wo, float3 wi) {
  if (b->dielectric || wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
  float3 f = b->color * (INV_PI * wi.z * (1.0f - b->metallic));
  if (b->metallic > 0.0f) {
    const float3 m = normalize3(wo + wi);
    const float g = ggx_g1(wo, b->alpha) * ggx_g1(wi, b->alpha);
    f += schlick(b->color, dot3(wi, m)) * (b->metallic * ggx_d(m, b->alpha) * g / (4.0f * wo.z));
  }
  return f;
}

float bsdf_pdf(const Bsdf* b, float3 wo, float3 wi) {
  if (b->dielectric || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  float p = (1.0f - b->metallic) * wi.z * INV_PI;
  if (b->metallic > 0.0f) {
    const float3 m = normalize3(wo + wi);
    p += b->metallic * ggx_g1(wo, b->alpha) * ggx_d(m, b->alpha) / (4.0f * wo.z);
  }
  return p;
}

// Returns false when the path should end.
bool bsdf_sample(const Bsdf* b, float3 wo, float u_lobe, float u1, float u2, BsdfSample* out) {
  if (b->dielectric) {
    const bool inside = wo.z < 0.0f;
    const float3 w = inside ? -wo : wo;
    const float eta = inside ? 1.0f / b->ior : b->ior;
    const float3 m = sample_ggx_vndf(w, b->alpha, u1, u2);
    const float cos_o = dot3(w, m);
    const float fr = fresnel_dielectric(cos_o, eta);
    float3 wi;
    float scale = 1.0f;
    if (u_lobe < fr) {
      wi = reflect3(w, m);
      if (wi.z <= 0.0f) return false;
    } else {
      const float sin2_t = (1.0f - cos_o * cos_o) / (eta * eta);
      const float cos_t = sqrt(fmax(0.0f, 1.0f - sin2_t));
      wi = m * (cos_o / eta - cos_t) - w * (1.0f / eta);
      if (wi.z >= 0.0f) return false;
      scale = 1.0f / (eta * eta);
    }
    out->weight = (float3)(scale * ggx_g1((float3)(wi.x, wi.y, fabs(wi.z)), b->alpha));
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
