// The scene as flat arrays for the OpenCL kernel: BVH, per-triangle shading records,
// materials, light tables and textures. Built on the host once per device (no OpenCL
// here, so it is testable alone). Every struct mirrors one in kernels/common.cl; they use
// float arrays, never float3 (16 bytes in OpenCL C), so host and device layouts agree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "device/opencl/bvh_flatten.h"
#include "render/path_tracer.h"

namespace multiray {

// Material with the Bsdf constructor's clamping already applied (see render/bsdf.cpp).
struct ClMaterial {
  float color[3];
  int32_t texture;  // index into ClScene::textures or -1
  float emission[3];
  float metallic;  // clamped to [0, 1]
  float alpha;     // GGX alpha = max(roughness^2, 1e-3)
  float ior;       // > 1
  uint32_t dielectric;
  uint32_t emissive;  // max component of emission > 0
};
static_assert(sizeof(ClMaterial) == 48);

// One emissive triangle of the LightSampler, in the sampler's order.
struct ClLight {
  float a[3];
  float pdf_area;  // selection probability / area
  float b[3];
  uint32_t prim;
  float c[3];
  float pad0;
  float radiance[3];
  float pad1;
};
static_assert(sizeof(ClLight) == 64);

struct ClTexture {
  uint32_t offset;  // first texel in ClScene::texels
  int32_t width, height;
  int32_t pad;
};

struct ClScene {
  FlatBvh bvh;
  std::vector<TriangleShading> shading;  // per scene triangle (64 bytes each)
  std::vector<ClMaterial> materials;
  std::vector<ClLight> lights;
  std::vector<float> light_cdf;          // LightSampler::cdf()
  std::vector<float> light_pdf_by_prim;  // LightSampler::pdf_by_prim()
  std::vector<uint32_t> texels;          // every texture's 8-bit sRGB texels, concatenated
  std::vector<ClTexture> textures;
  std::vector<float> srgb_to_linear;  // 256 entries, the CPU's own decoding table
  Vec3 environment;
  float ray_eps = 0;  // ray-origin offset, as PathTracer's
};

// What `scene` uses that the OpenCL kernel does not render (one phrase), or "".
std::string cl_unsupported_feature(const Scene& scene);

// Throws DeviceError when the BVH cannot be built (see build_flat_bvh) or the scene
// uses a feature of cl_unsupported_feature().
ClScene build_cl_scene(const RenderScene& rs);

}  // namespace multiray
