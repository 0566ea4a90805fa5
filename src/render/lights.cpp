#include "render/lights.h"

#include <algorithm>

#include "render/surface.h"

namespace multiray {

LightSampler::LightSampler(const Scene& scene) : scene_(scene) {
  std::vector<double> power;
  std::vector<float> area;
  double total = 0;
  for (size_t t = 0; t < scene.triangle_count(); ++t) {
    const Material& m = scene.materials[scene.material_ids[t]];
    if (max_component(m.emission) <= 0) continue;
    const Vec3 a = scene.positions[scene.indices[3 * t]],
               b = scene.positions[scene.indices[3 * t + 1]],
               c = scene.positions[scene.indices[3 * t + 2]];
    const float ar = 0.5f * length(cross(b - a, c - a));
    if (!(ar > 0)) continue;
    float lum = luminance(m.emission);
    if (m.emission_texture >= 0) {
      // Estimated from the texture at the corners and the centre. A triangle estimated
      // dark is never chosen; its light still arrives by BSDF sampling, which MIS then
      // weights fully (the light density there is 0), so nothing is lost or counted twice.
      lum = luminance(mean_emission(t));
      if (!(lum > 0)) continue;
    }
    tris_.push_back(uint32_t(t));
    area.push_back(ar);
    power.push_back(double(ar) * std::max(lum, 1e-6f));
    total += power.back();
  }
  total_power_ = total;
  pdf_by_prim_.assign(scene.triangle_count(), 0.0f);
  double acc = 0;
  for (size_t i = 0; i < tris_.size(); ++i) {
    acc += power[i];
    cdf_.push_back(float(acc / total));
    pdf_by_prim_[tris_[i]] = float(power[i] / total) / area[i];
  }
  if (!cdf_.empty()) cdf_.back() = 1.0f;
  for (uint32_t t : tris_) {
    LightRecord l{};
    const auto put = [](float out[3], Vec3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; };
    put(l.a, scene.positions[scene.indices[3 * t]]);
    put(l.b, scene.positions[scene.indices[3 * t + 1]]);
    put(l.c, scene.positions[scene.indices[3 * t + 2]]);
    put(l.radiance, scene.materials[scene.material_ids[t]].emission);
    l.pdf_area = pdf_by_prim_[t];
    l.prim = t;
    records_.push_back(l);
  }
}

Vec2 LightSampler::uv_at(uint32_t t, float b1, float b2) const {
  if (scene_.uvs.empty()) return Vec2{};
  const Vec2 a = scene_.uvs[scene_.indices[3 * t]], b = scene_.uvs[scene_.indices[3 * t + 1]],
             c = scene_.uvs[scene_.indices[3 * t + 2]];
  const float b0 = 1.0f - b1 - b2;
  return {a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2};
}

Vec3 LightSampler::mean_emission(uint32_t t) const {
  const Material& m = scene_.materials[scene_.material_ids[t]];
  const float third = 1.0f / 3.0f;
  const Vec3 sum =
      emission_at(scene_, m, uv_at(t, 0, 0)) + emission_at(scene_, m, uv_at(t, 1, 0)) +
      emission_at(scene_, m, uv_at(t, 0, 1)) + emission_at(scene_, m, uv_at(t, third, third));
  return sum * 0.25f;
}

float LightSampler::pdf_area(uint32_t prim) const {
  return prim < pdf_by_prim_.size() ? pdf_by_prim_[prim] : 0.0f;
}

}  // namespace multiray
