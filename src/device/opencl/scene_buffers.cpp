#include "device/opencl/scene_buffers.h"

#include <algorithm>
#include <type_traits>

#include "core/error.h"
#include "render/bsdf.h"

namespace multiray {

namespace {

ClMaterial to_cl(const Material& m) {
  ClMaterial c{};
  c.color[0] = m.base_color.x, c.color[1] = m.base_color.y, c.color[2] = m.base_color.z;
  c.texture = m.base_color_texture;
  c.emission[0] = m.emission.x, c.emission[1] = m.emission.y, c.emission[2] = m.emission.z;
  c.emission_texture = m.emission_texture;
  c.metallic = m.metallic;
  c.roughness = m.roughness;
  // The Bsdf's choices that no texture changes, made once here.
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

void put(float out[3], Vec3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

template <class T>
uint32_t append(std::vector<float>& out, const std::vector<T>& v) {
  const size_t at = out.size();
  if (at + v.size() * (sizeof(T) / sizeof(float)) > UINT32_MAX)
    throw DeviceError("OpenCL: the environment map exceeds 4 G floats");
  for (const T& x : v) {
    if constexpr (std::is_same_v<T, float>) {
      out.push_back(x);
    } else {
      out.insert(out.end(), {x.x, x.y, x.z});
    }
  }
  return uint32_t(at);
}

// The environment light as the kernel samples it: every number from the CPU's own
// EnvironmentLight, so both sample the same distribution.
void build_sky(const RenderScene& rs, ClScene& c) {
  const Scene& s = rs.scene;
  const EnvironmentLight& env = rs.environment;
  ClSky& k = c.sky;
  put(k.constant_sky, s.environment);
  k.choice = rs.environment_choice();
  const EnvFrame f = environment_frame(s.up);
  put(k.frame_x, f.x), put(k.frame_up, f.up), put(k.frame_z, f.z);
  k.sun_on = s.sun.on() ? 1u : 0u;
  put(k.sun_dir, s.sun.direction), put(k.sun_radiance, s.sun.radiance);
  k.sun_cos = env.sun_cos(), k.sun_pdf = env.sun_pdf(), k.p_sun = env.sun_probability();
  k.sky_on = env.has_sky() ? 1u : 0u;
  k.on = env.on() ? 1u : 0u;
  // The tables are empty exactly when the EnvironmentLight uses no map.
  if (env.row_cdf().empty()) return;
  const EnvironmentMap& map = *s.environment_map;
  k.map_width = map.width, k.map_height = map.height;
  k.row_cdf = append(c.sky_data, env.row_cdf());
  k.row_pdf = append(c.sky_data, env.row_pdf());
  k.col_cdf = append(c.sky_data, env.column_cdf());
  k.pix_pdf = append(c.sky_data, env.pixel_pdf());
  // EnvironmentLight::map_radiance's product, done once here (the same float product).
  std::vector<Vec3> scaled(map.radiance.size());
  for (size_t i = 0; i < scaled.size(); ++i) scaled[i] = map.radiance[i] * s.environment_map_scale;
  k.map = append(c.sky_data, scaled);
}

ClCompactScene to_cl(const CompactScene& c) {
  ClCompactScene k;
  const CompactMesh& m = c.mesh;
  ClCompactInfo& i = k.info;
  put(i.origin, m.grid.origin);
  i.cell = m.grid.cell;
  i.step = m.grid.step;
  i.has_normals = m.normals.empty() ? 0u : 1u;
  i.has_uvs = m.uvs.empty() ? 0u : 1u;
  i.has_nodes = c.bvh.nodes.empty() ? 0u : 1u;
  put(i.root_lo, c.bvh.root.lo), put(i.root_hi, c.bvh.root.hi);
  for (int a = 0; a < 2; ++a)
    i.uv_step[a] = m.uv_coding.step[a], i.uv_period_log2[a] = m.uv_coding.period_log2[a],
    i.uv_shift_base[a] = m.uv_shifts.base[a];
  i.widths = m.indices.width | m.material_ids.width << 8 | m.uv_shifts.bits[0] << 16 |
             m.uv_shifts.bits[1] << 24;
  k.nodes = c.bvh.nodes;
  k.prims = c.bvh.prims.words;
  i.prim_bits = c.bvh.prims.width;
  k.positions = m.positions;
  k.cells = m.grid.cells;
  k.indices = m.indices.words;
  k.normals = m.normals;
  k.uvs = m.uvs;
  k.uv_shifts = m.uv_shifts.packed.words;
  k.material_ids = m.material_ids.words;
  return k;
}

template <class T>
uint64_t bytes_of(const std::vector<T>& v) {
  return uint64_t(v.size()) * sizeof(T);
}

}  // namespace

uint64_t cl_scene_bytes(const ClScene& c) {
  const ClCompactScene& k = c.compact;
  return bytes_of(c.bvh.nodes) + bytes_of(c.bvh.triangles) + bytes_of(c.shading) +
         (c.is_compact ? sizeof(ClCompactInfo) : 0) + bytes_of(k.nodes) + bytes_of(k.prims) +
         bytes_of(k.positions) + bytes_of(k.cells) + bytes_of(k.indices) + bytes_of(k.normals) +
         bytes_of(k.uvs) + bytes_of(k.uv_shifts) + bytes_of(k.material_ids) +
         bytes_of(c.materials) + bytes_of(c.lights) + bytes_of(c.light_cdf) +
         bytes_of(c.light_pdf_by_prim) + bytes_of(c.texels) + bytes_of(c.textures) +
         bytes_of(c.texel_luts) + bytes_of(c.tangents) + sizeof(ClSky) + bytes_of(c.sky_data);
}

// Everything the CPU path tracer renders is rendered by the kernel too (environment map,
// sun, per-texel materials, cut-outs); new features are refused here until ported.
std::string cl_unsupported_feature(const Scene&) { return {}; }

ClScene build_cl_scene(const RenderScene& rs) {
  const Scene& s = rs.scene;
  if (const std::string why = cl_unsupported_feature(s); !why.empty())
    throw DeviceError("OpenCL: " + why +
                      ", which the OpenCL kernel does not render yet; use CPU devices for it");
  ClScene c;
  if (rs.compact) {
    c.is_compact = true;
    c.compact = to_cl(*rs.compact);
  } else {
    c.bvh = build_flat_bvh(s);
    c.shading = rs.shading;
  }
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
    c.textures.push_back(
        ClTexture{uint32_t(c.texels.size()), t.width, t.height, uint32_t(t.coding)});
    c.texels.insert(c.texels.end(), t.texels.begin(), t.texels.end());
  }
  // The CPU's own decoding tables, so both backends turn a byte into exactly the same
  // value.
  for (TexelCoding coding : {TexelCoding::srgb, TexelCoding::linear, TexelCoding::signed_unit}) {
    const float* lut = texel_decoding_table(coding);
    c.texel_luts.insert(c.texel_luts.end(), lut, lut + 256);
  }
  for (const TriangleTangent& t : rs.tangents)
    c.tangents.insert(c.tangents.end(), {t.u.x, t.u.y, t.u.z, t.sign});
  c.cutouts = std::any_of(s.materials.begin(), s.materials.end(),
                          [](const Material& m) { return m.may_be_transparent(); });
  build_sky(rs, c);

  // The same offset as PathTracer's constructor.
  c.ray_eps = 2e-5f * std::max(1.0f, max_component(s.bounds().extent()));
  return c;
}

}  // namespace multiray
