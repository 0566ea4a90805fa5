#include "render/scene_records.h"

#include <cstddef>

#include "render/bsdf.h"
#include "render/shading_data.h"
#include "render/shared/bvh_records.h"

namespace multiray {

// The records' layout is OpenCL C's too: every field where the kernels expect it.
static_assert(offsetof(MaterialRecord, emission) == 16 && offsetof(MaterialRecord, ior) == 40 &&
              offsetof(MaterialRecord, alpha_cutoff) == 72);
static_assert(offsetof(LightRecord, b) == 16 && offsetof(LightRecord, prim) == 28 &&
              offsetof(LightRecord, radiance) == 48);
static_assert(offsetof(FlatNode, hi) == 24 && offsetof(FlatNode, child) == 48);
static_assert(offsetof(FlatTriangle, e1n) == 16 && offsetof(FlatTriangle, e2) == 32);
static_assert(offsetof(CompactNode, child) == 12);
// The kernels read TriangleShading through StoredShading.
static_assert(sizeof(TriangleShading) == sizeof(StoredShading) &&
              offsetof(TriangleShading, normal) == offsetof(StoredShading, normal) &&
              offsetof(TriangleShading, uv) == offsetof(StoredShading, uv) &&
              offsetof(TriangleShading, material) == offsetof(StoredShading, material));
static_assert(offsetof(CompactInfo, root_lo) == 16 && offsetof(CompactInfo, widths) == 68 &&
              offsetof(CompactInfo, has_uvs) == 84);
static_assert(offsetof(SkyRecord, frame_x) == 16 && offsetof(SkyRecord, sun_on) == 76 &&
              offsetof(SkyRecord, map_width) == 96 && offsetof(SkyRecord, map_scale) == 124);

MaterialRecord material_record(const Material& m) {
  MaterialRecord c{};
  c.color[0] = m.base_color.x, c.color[1] = m.base_color.y, c.color[2] = m.base_color.z;
  c.texture = m.base_color_texture;
  c.emission[0] = m.emission.x, c.emission[1] = m.emission.y, c.emission[2] = m.emission.z;
  c.emission_texture = m.emission_texture;
  c.metallic = m.metallic;
  c.roughness = m.roughness;
  c.ior = material_ior(m);
  c.dielectric = material_is_dielectric(m) ? 1u : 0u;
  c.emissive = max_component(m.emission) > 0 ? 1u : 0u;
  c.metallic_roughness_texture = m.metallic_roughness_texture;
  c.normal_texture = m.normal_texture;
  c.normal_scale = m.normal_scale;
  c.opacity = m.opacity;
  c.alpha_mode = uint32_t(m.alpha_mode);
  c.alpha_cutoff = m.alpha_cutoff;
  return c;
}

TextureView texture_view(const Texture& t) {
  return TextureView{t.texels.data(), texel_decoding_table(t.coding),
                     texel_decoding_table(TexelCoding::linear), t.width, t.height};
}

}  // namespace multiray
