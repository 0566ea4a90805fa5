#include "render/surface.h"

#include "render/scene_records.h"

namespace multiray {

Vec3 emission_at(const Scene& scene, const Material& m, Vec2 uv) {
  if (m.emission_texture < 0) return m.emission;
  const TextureView t = texture_view(scene.textures[size_t(m.emission_texture)]);
  return m.emission * texture_sample(&t, uv);
}

float alpha_at(const Scene& scene, const Material& m, Vec2 uv) {
  if (m.base_color_texture < 0) return m.opacity;
  const TextureView t = texture_view(scene.textures[size_t(m.base_color_texture)]);
  return m.opacity * texture_sample_alpha(&t, uv);
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
