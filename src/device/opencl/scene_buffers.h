// The scene as flat arrays for the OpenCL kernel: BVH, per-triangle shading records,
// materials, light tables and textures. Built on the host once per device (no OpenCL
// here, so it is testable alone). Every struct mirrors one in kernels/common.cl; they use
// float arrays, never float3 (16 bytes in OpenCL C), so host and device layouts agree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/compact_scene.h"
#include "render/flat_bvh.h"
#include "render/path_tracer.h"

namespace multiray {

// Material with its raw factors: the kernel multiplies them by their textures and then
// clamps them with bsdf_params (kernels/surface.cl, render/shared/bsdf.h).
struct ClMaterial {
  float color[3];
  int32_t texture;  // base colour texture (index into ClScene::textures) or -1
  float emission[3];
  int32_t emission_texture;  // or -1
  float metallic;
  float roughness;  // perceptual
  float ior;        // > 1
  uint32_t dielectric;
  uint32_t emissive;  // max component of emission > 0
  int32_t metallic_roughness_texture;
  int32_t normal_texture;
  float normal_scale;
  float opacity;
  uint32_t alpha_mode;  // AlphaMode: 0 opaque, 1 mask, 2 blend
  float alpha_cutoff;
  float pad;
};
static_assert(sizeof(ClMaterial) == 80);

// One emissive triangle of the LightSampler, in the sampler's order.
struct ClLight {
  float a[3];
  float pdf_area;  // selection probability / area
  float b[3];
  uint32_t prim;
  float c[3];
  float pad0;
  float radiance[3];  // the emission factor; the kernel applies the emission texture
  float pad1;
};
static_assert(sizeof(ClLight) == 64);

struct ClTexture {
  uint32_t offset;  // first texel in ClScene::texels
  int32_t width, height;
  uint32_t coding;  // TexelCoding, the table of ClScene::texel_luts to decode with
};

// The EnvironmentLight (render/environment.h) and RenderScene::environment_choice(); the
// map's tables and radiance live in ClScene::sky_data at the offsets given here.
struct ClSky {
  float constant_sky[3];
  float choice;
  float frame_x[3];
  float sun_cos;
  float frame_up[3];
  float sun_pdf;
  float frame_z[3];
  float p_sun;
  float sun_dir[3];
  uint32_t sun_on;
  float sun_radiance[3];
  uint32_t sky_on;
  int32_t map_width, map_height;  // 0 x 0 without a map
  uint32_t on;
  uint32_t row_cdf, row_pdf, col_cdf, pix_pdf, map;  // offsets into sky_data
};
static_assert(sizeof(ClSky) == 128);

// CompactInfo of kernels/common.cl: the scalars of the compact scene.
struct ClCompactInfo {
  float origin[3];
  float cell;
  float root_lo[3];
  uint32_t has_nodes;
  float root_hi[3];
  uint32_t has_normals;
  float uv_step[2];
  uint32_t uv_period_log2[2];
  float step;
  // Bit widths of the packed arrays (render/compact_packed.h): vertex index in bits 0-7,
  // material id 8-15, uv shift offsets u 16-23 and v 24-31.
  uint32_t widths;
  int32_t uv_shift_base[2];
  uint32_t prim_bits;  // width of the tree's packed triangle references
  uint32_t has_uvs;    // 0: no uvs, `uvs` is empty (the kernel must not read it)
  uint32_t pad[2];
};
static_assert(sizeof(ClCompactInfo) == 96);

// The compact scene's arrays as the kernel reads them (render/compact_scene.h): its nodes
// and QuantizedPosition are uploaded byte for byte, the cell-index table as 3 ushorts per
// geometry cell, the bit-packed faces, material ids and uv shifts as their 32-bit words.
struct ClCompactScene {
  ClCompactInfo info{};
  std::vector<CompactNode> nodes;
  std::vector<uint32_t> prims;
  std::vector<QuantizedPosition> positions;
  std::vector<uint16_t> cells;
  std::vector<uint32_t> indices, material_ids, uv_shifts;
  std::vector<uint16_t> normals, uvs;
};

struct ClScene {
  // Full precision: the flat BVH and a shading record per scene triangle (64 bytes each).
  // With a compact scene both are empty and `compact` holds the quantized mesh and tree.
  bool is_compact = false;
  FlatBvh bvh;
  std::vector<TriangleShading> shading;
  ClCompactScene compact;
  std::vector<ClMaterial> materials;
  std::vector<ClLight> lights;
  std::vector<float> light_cdf;          // LightSampler::cdf()
  std::vector<float> light_pdf_by_prim;  // LightSampler::pdf_by_prim()
  std::vector<uint32_t> texels;          // every texture's 8-bit texels, concatenated
  std::vector<ClTexture> textures;
  std::vector<float> texel_luts;  // 3 x 256: the CPU's decoding tables in TexelCoding order
  std::vector<float> tangents;    // 4 per triangle (u, sign), empty without normal maps
  ClSky sky{};
  // Map tables, then its radiance (3 floats per pixel, times the map's scale).
  std::vector<float> sky_data;
  bool cutouts = false;  // some material has an alpha mode
  float ray_eps = 0;     // ray-origin offset, as PathTracer's
};

// What `scene` uses that the OpenCL kernel does not render (one phrase), or "".
std::string cl_unsupported_feature(const Scene& scene);

// The buffers for `rs`: the compact scene when rs.compact is set (lights, materials,
// textures, tangents and the sky stay full precision in both). Throws DeviceError when
// the BVH cannot be built (see build_flat_bvh) or the scene uses a feature of
// cl_unsupported_feature().
ClScene build_cl_scene(const RenderScene& rs);

// Bytes of the scene buffers the device holds (every array of `c`).
uint64_t cl_scene_bytes(const ClScene& c);

}  // namespace multiray
