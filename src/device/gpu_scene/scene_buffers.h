// The scene as flat arrays for a GPU-style backend's kernels (OpenCL today, CUDA or HIP
// alike): BVH or compact tree, per-triangle shading records, materials, light tables and
// textures. Backend-neutral: built on the host once per device with no GPU API, so any
// backend uploads the same arrays (and it is testable alone). Materials, lights, textures
// and the sky are the integrator's records (render/shared/scene_records.h, one layout on
// both sides); the BVH records (flat and compact nodes, triangles, the stored
// shading record, the compact scene's scalars) are render/shared/bvh_records.h's. Float arrays,
// never float3 (16 bytes in OpenCL C), so host and device layouts agree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/compact_scene.h"
#include "render/flat_bvh.h"
#include "render/path_tracer.h"

namespace multiray {

// The compact scene's arrays as the kernel reads them (render/compact_scene.h): its nodes
// and QuantizedPosition are uploaded byte for byte, the cell-index table as 3 ushorts per
// geometry cell, the bit-packed faces, material ids and uv shifts as their 32-bit words.
struct GpuCompactScene {
  CompactInfo info{};
  std::vector<CompactNode> nodes;
  std::vector<uint32_t> prims;
  std::vector<QuantizedPosition> positions;
  std::vector<uint16_t> cells;
  std::vector<uint32_t> indices, material_ids, uv_shifts;
  std::vector<uint16_t> normals, uvs;
};

struct GpuScene {
  // Full precision: the flat BVH and a shading record per scene triangle (64 bytes each).
  // With a compact scene both are empty and `compact` holds the quantized mesh and tree.
  bool is_compact = false;
  FlatBvh bvh;
  std::vector<TriangleShading> shading;
  GpuCompactScene compact;
  std::vector<MaterialRecord> materials;  // RenderScene's
  std::vector<LightRecord> lights;        // the LightSampler's
  std::vector<float> light_cdf;           // LightSampler::cdf()
  std::vector<float> light_pdf_by_prim;   // LightSampler::pdf_by_prim()
  std::vector<uint32_t> texels;           // every texture's 8-bit texels, concatenated
  std::vector<TextureRecord> textures;
  std::vector<float> texel_luts;  // 3 x 256: the CPU's decoding tables in TexelCoding order
  std::vector<float> tangents;    // 4 per triangle (u, sign), empty without normal maps
  SkyRecord sky{};
  // The map's sampling tables (EnvironmentLight::tables()), then its radiance (3 floats a
  // pixel, unscaled); the kernel reads the radiance after the last table (pix_pdf + w x h).
  std::vector<float> sky_data;
  bool cutouts = false;  // some material has an alpha mode
  float ray_eps = 0;     // ray-origin offset, as PathTracer's
};

// What `scene` uses that the GPU kernels do not render (one phrase), or "".
std::string gpu_unsupported_feature(const Scene& scene);

// The buffers for `rs`: the compact scene when rs.compact is set (lights, materials,
// textures, tangents and the sky stay full precision in both). Throws DeviceError when
// the BVH cannot be built (see build_flat_bvh) or the scene uses a feature of
// gpu_unsupported_feature().
GpuScene build_gpu_scene(const RenderScene& rs);

// Bytes of the scene buffers the device holds (every array of `c`).
uint64_t gpu_scene_bytes(const GpuScene& c);

}  // namespace multiray
