#include "device/opencl/scene_buffers.h"

#include <algorithm>

#include "core/error.h"

namespace multiray {

namespace {

ClMaterial to_cl(const Material& m) {
  ClMaterial c{};
  c.color[0] = m.base_color.x, c.color[1] = m.base_color.y, c.color[2] = m.base_color.z;
  c.texture = m.base_color_texture;
  c.emission[0] = m.emission.x, c.emission[1] = m.emission.y, c.emission[2] = m.emission.z;
  // The same clamping as the Bsdf constructor, done once here instead of per hit.
  c.metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  c.alpha = std::max(m.roughness * m.roughness, 1e-3f);
  c.ior = m.ior > 1.0f ? m.ior : 1.5f;
  c.dielectric = m.transmission > 0.5f ? 1u : 0u;
  c.emissive = max_component(m.emission) > 0 ? 1u : 0u;
  return c;
}

void put(float out[3], Vec3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

}  // namespace

std::string cl_unsupported_feature(const Scene& s) {
  for (const Material& m : s.materials) {
    const std::string what = "material '" + m.name + "' has ";
    if (m.emission_texture >= 0) return what + "an emission texture";
    if (m.metallic_roughness_texture >= 0) return what + "a metallic-roughness texture";
    if (m.normal_texture >= 0) return what + "a normal map";
    if (m.may_be_transparent()) return what + "an alpha mode (mask or blend)";
    if (m.base_color_texture >= 0 &&
        s.textures[size_t(m.base_color_texture)].coding != TexelCoding::srgb)
      return what + "a base colour texture that is not sRGB";
  }
  if (s.environment_map) return "the scene has an environment map";
  if (s.sun.on()) return "the scene has a sun";
  return {};
}

ClScene build_cl_scene(const RenderScene& rs) {
  const Scene& s = rs.scene;
  if (const std::string why = cl_unsupported_feature(s); !why.empty())
    throw DeviceError("OpenCL: " + why +
                      ", which the OpenCL kernel does not render yet; use CPU devices for it");
  ClScene c;
  c.bvh = build_flat_bvh(s);
  c.shading = rs.shading;
  for (const Material& m : s.materials) c.materials.push_back(to_cl(m));

  const std::vector<uint32_t>& tris = rs.lights.triangles();
  for (uint32_t t : tris) {
    ClLight l{};
    put(l.a, s.positions[s.indices[3 * t]]);
    put(l.b, s.positions[s.indices[3 * t + 1]]);
    put(l.c, s.positions[s.indices[3 * t + 2]]);
    put(l.radiance, s.materials[s.material_ids[t]].emission);
    l.pdf_area = rs.lights.pdf_area(t);
    l.prim = t;
    c.lights.push_back(l);
  }
  c.light_cdf = rs.lights.cdf();
  c.light_pdf_by_prim = rs.lights.pdf_by_prim();

  for (const Texture& t : s.textures) {
    if (c.texels.size() + t.texels.size() > UINT32_MAX)
      throw DeviceError("OpenCL: the scene's textures exceed 4 G texels");
    c.textures.push_back(ClTexture{uint32_t(c.texels.size()), t.width, t.height, 0});
    c.texels.insert(c.texels.end(), t.texels.begin(), t.texels.end());
  }
  // The CPU's own sRGB decoding table, so both backends turn a byte into exactly the same
  // linear value.
  const float* lut = texel_decoding_table(TexelCoding::srgb);
  c.srgb_to_linear.assign(lut, lut + 256);

  c.environment = s.environment;
  // The same offset as PathTracer's constructor.
  c.ray_eps = 2e-5f * std::max(1.0f, max_component(s.bounds().extent()));
  return c;
}

}  // namespace multiray
