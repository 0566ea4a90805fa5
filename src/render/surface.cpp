#include "render/surface.h"

namespace multiray {

Vec3 emission_at(const Scene& scene, const Material& m, Vec2 uv) {
  if (m.emission_texture < 0) return m.emission;
  return m.emission * scene.textures[size_t(m.emission_texture)].sample(uv);
}

namespace {

// The normal map's tangent-space normal at `uv` applied to `ns` (glTF 2.0 §3.9.3: x along
// the tangent, y along the bitangent, z along the normal; x and y scaled by the scale).
Vec3 tilted_normal(const Texture& map, float scale, Vec2 uv, Vec3 ns, Vec3 ng,
                   const TriangleTangent& tangent) {
  const Vec3 m = map.sample(uv);
  const float x = m.x * scale, y = m.y * scale;
  if ((x == 0 && y == 0) || !(dot(tangent.u, tangent.u) > 0)) return ns;  // flat: untouched
  const Vec3 t = tangent.u - ns * dot(ns, tangent.u);
  if (!(dot(t, t) > 1e-12f)) return ns;
  const Vec3 tu = normalize(t);
  const Vec3 b = cross(ns, tu) * tangent.sign;
  const Vec3 n = normalize(tu * x + b * y + ns * std::max(m.z, 0.0f));
  return is_finite(n) && dot(n, ng) > 0 ? n : ns;
}

}  // namespace

SurfacePoint surface_at(const Scene& scene, const Material& m, Vec2 uv, Vec3 ns, Vec3 ng,
                        const TriangleTangent* tangent, const Texture::Footprint* base_footprint) {
  SurfacePoint sp;
  sp.base_color = m.base_color;
  if (m.base_color_texture >= 0) {
    const Texture& t = scene.textures[size_t(m.base_color_texture)];
    sp.base_color *= base_footprint ? t.sample_at(*base_footprint) : t.sample(uv);
  }
  sp.metallic = m.metallic;
  sp.roughness = m.roughness;
  if (m.metallic_roughness_texture >= 0) {
    const Vec3 mr = scene.textures[size_t(m.metallic_roughness_texture)].sample(uv);
    sp.roughness *= mr.y;
    sp.metallic *= mr.z;
  }
  sp.ns = ns;
  if (m.normal_texture >= 0 && tangent != nullptr)
    sp.ns = tilted_normal(scene.textures[size_t(m.normal_texture)], m.normal_scale, uv, ns, ng,
                          *tangent);
  return sp;
}

float alpha_at(const Scene& scene, const Material& m, Vec2 uv) {
  if (m.base_color_texture < 0) return m.opacity;
  return m.opacity * scene.textures[size_t(m.base_color_texture)].sample_alpha(uv);
}

bool passes_through(const Scene& scene, const Material& m, Vec2 uv, float u) {
  switch (m.alpha_mode) {
    case AlphaMode::mask:
      return alpha_at(scene, m, uv) < m.alpha_cutoff;
    case AlphaMode::blend:
      return u >= alpha_at(scene, m, uv);
    default:
      return false;
  }
}

}  // namespace multiray
