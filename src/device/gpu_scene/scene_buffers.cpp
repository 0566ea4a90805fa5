#include "device/gpu_scene/scene_buffers.h"

#include <algorithm>
#include <type_traits>

#include "core/error.h"

namespace multiray {

namespace {

// The environment light as the integrator samples it: the CPU's own record and tables,
// then the map's radiance (unscaled, as the CPU reads it: the record's map_scale applies).
void build_sky(const RenderScene& rs, GpuScene& c) {
  const EnvironmentLight& env = rs.environment;
  c.sky = env.record();
  c.sky.choice = rs.environment_choice();
  c.sky_data = env.tables();
  const float* map = env.map();
  if (map == nullptr) return;
  const size_t floats = 3 * size_t(c.sky.map_width) * size_t(c.sky.map_height);
  if (c.sky_data.size() + floats > UINT32_MAX)
    throw DeviceError("GPU scene: the environment map exceeds 4 G floats");
  c.sky_data.insert(c.sky_data.end(), map, map + floats);
}

GpuCompactScene to_gpu(const CompactScene& c) {
  GpuCompactScene k;
  const CompactMesh& m = c.mesh;
  k.info = c.info;
  k.nodes = c.bvh.nodes;
  k.prims = c.bvh.prims.words;
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

uint64_t gpu_scene_bytes(const GpuScene& c) {
  const GpuCompactScene& k = c.compact;
  return bytes_of(c.bvh.nodes) + bytes_of(c.bvh.triangles) + bytes_of(c.shading) +
         (c.is_compact ? sizeof(CompactInfo) : 0) + bytes_of(k.nodes) + bytes_of(k.prims) +
         bytes_of(k.positions) + bytes_of(k.cells) + bytes_of(k.indices) + bytes_of(k.normals) +
         bytes_of(k.uvs) + bytes_of(k.uv_shifts) + bytes_of(k.material_ids) +
         bytes_of(c.materials) + bytes_of(c.lights) + bytes_of(c.light_cdf) +
         bytes_of(c.light_pdf_by_prim) + bytes_of(c.texels) + bytes_of(c.textures) +
         bytes_of(c.texel_luts) + bytes_of(c.tangents) + sizeof(SkyRecord) + bytes_of(c.sky_data);
}

// Everything the CPU path tracer renders is rendered by the kernel too (environment map,
// sun, per-texel materials, cut-outs); new features are refused here until ported.
std::string gpu_unsupported_feature(const Scene&) { return {}; }

GpuScene build_gpu_scene(const RenderScene& rs) {
  const Scene& s = rs.scene;
  if (const std::string why = gpu_unsupported_feature(s); !why.empty())
    throw DeviceError("GPU scene: " + why +
                      ", which the GPU kernels do not render yet; use CPU devices for it");
  GpuScene c;
  if (rs.compact) {
    c.is_compact = true;
    c.compact = to_gpu(*rs.compact);
  } else {
    c.bvh = build_flat_bvh(s);
    c.shading = rs.shading;
  }
  c.materials = rs.materials;
  c.lights = rs.lights.records();
  c.light_cdf = rs.lights.cdf();
  c.light_pdf_by_prim = rs.lights.pdf_by_prim();

  for (const Texture& t : s.textures) {
    if (c.texels.size() + t.texels.size() > UINT32_MAX)
      throw DeviceError("GPU scene: the scene's textures exceed 4 G texels");
    c.textures.push_back(
        TextureRecord{uint32_t(c.texels.size()), t.width, t.height, uint32_t(t.coding)});
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
