// The interface of the render_rect kernel (kernels/path_tracer.cl), declared once for both
// sides: compiled as OpenCL C (embedded first in the kernel source, see CMakeLists.txt
// here; the disk cache keys on that source, so editing this file rebuilds the binaries)
// and as C++ by opencl_path_tracer.cpp. Written in render/shared/language.h's dialect
// (whose typedefs mr_float4, mr_int4, mr_uint, ... it uses); the camera block opening it is
// render/shared/camera.h's, shared with volume_params.h and the CPU's PinholeCamera.
//
// LaunchParams: the scalars of one launch, passed as one small `__constant` buffer that
// the host rewrites when it changes. Not a by-value struct argument: OpenCL leaves the
// ABI of aggregate kernel arguments to the driver, PoCL mapped them wrongly for years
// (pocl issues #1 and #197: split structs, miscounted arguments) and its maintainers
// advise against them; a buffer is plain bytes, the contract every scene buffer already
// relies on. Its layout is explicit: every member sits at a multiple of its own size with
// the padding spelled out, the size is a multiple of 16 and no float3 is used (16 bytes in
// OpenCL C), so there is no implicit padding on either side. The host checks every offset;
// the kernel checks the size, which with no implicit padding fixes every offset too.
//
// MR_RENDER_RECT_ARGS: every argument of render_rect in order, X(name, OpenCL C type),
// entries separated by SEP(). The kernel's parameter list and the host's argument indices
// (MR_ARG_<name>) and names (kRenderRectArgNames) are expanded from it, so adding an
// argument is one line here (plus its use in the kernel and its buffer on the host).
//
// An include guard, not #pragma once: in the kernel this text is part of the main file.
#ifndef MULTIRAY_DEVICE_OPENCL_KERNELS_LAUNCH_PARAMS_H
#define MULTIRAY_DEVICE_OPENCL_KERNELS_LAUNCH_PARAMS_H

#ifdef __cplusplus
#include <stddef.h>

#include "render/shared/camera.h"
#endif

#ifdef __cplusplus
namespace multiray {
#endif

// Byte offsets on the right.
typedef struct {
  CameraBlock camera;  //   0: PinholeCamera::block(), 80 bytes
  // x: the probability that next-event estimation samples the environment (the sky's
  // choice, or 0 when RenderSettings::sample_environment is off); w: the ray-origin
  // offset; y, z unused.
  mr_float4 env_choice_eps;  //  80
  // Unused (zero): the kernel reads its rects from the `batch` argument (batch_rects.h).
  // Pixels [x, x + z) x [y, y + w) of the view.
  mr_int4 rect;          //  96
  mr_ulong seed;         // 112
  mr_uint width;         // 120: of the view, in pixels
  mr_int spp;            // 124: samples per pixel when use_spp_map is 0
  mr_int max_bounces;    // 128
  mr_int rr_start;       // 132: Russian roulette from this depth on
  mr_uint frame;         // 136
  mr_uint view;          // 140
  mr_uint light_count;   // 144: entries of `lights`
  mr_int use_spp_map;    // 148: 1: spp_map[i] samples for work-item i
  mr_uint has_tangents;  // 152: 1: `tangents` holds one entry per triangle (normal maps)
  mr_uint cutouts;       // 156: 1: some material has an alpha mode (mask or blend)
  float sample_clamp;    // 160: RenderSettings::sample_clamp (0: off)
  // 164: ViewSetup::first_sample (progressive sampling); `frame` is then the seed frame
  mr_uint first_sample;
  // 168: 1: record the feature buffers (RenderSettings::feature_buffers) into `features`
  mr_uint feature_buffers;
  mr_uint pad;   // 172: unused, keeps the size a multiple of 16
} LaunchParams;  // 176

#ifdef MR_OPENCL_C
typedef char mr_launch_params_size_check[sizeof(LaunchParams) == 176 ? 1 : -1];
#endif

// clang-format off
#define MR_RENDER_RECT_ARGS(X, SEP)                   \
  X(nodes, const __global FlatNode*) SEP()            \
  X(tris, const __global FlatTriangle*) SEP()         \
  X(shading, const __global StoredShading*) SEP()     \
  X(materials, const __global MaterialRecord*) SEP()  \
  X(lights, const __global LightRecord*) SEP()        \
  X(light_cdf, const __global float*) SEP()           \
  X(light_pdf_by_prim, const __global float*) SEP()   \
  X(texels, const __global uint*) SEP()               \
  X(textures, const __global TextureRecord*) SEP()    \
  X(texel_luts, const __global float*) SEP()          \
  X(tangents, const __global float4*) SEP()           \
  X(sky, const __global SkyRecord*) SEP()             \
  X(sky_data, const __global float*) SEP()            \
  X(cnodes, const __global CompactNode*) SEP()        \
  X(prims, const __global uint*) SEP()                \
  X(qpos, const __global ushort*) SEP()               \
  X(cells, const __global ushort*) SEP()              \
  X(indices, const __global uint*) SEP()              \
  X(qnormals, const __global ushort*) SEP()           \
  X(quvs, const __global ushort*) SEP()               \
  X(uv_shifts, const __global uint*) SEP()            \
  X(material_ids, const __global uint*) SEP()         \
  X(compact, const __global CompactInfo*) SEP()       \
  X(batch, const __global BatchRects*) SEP()          \
  X(params, __constant LaunchParams*) SEP()           \
  X(spp_map, const __global uchar*) SEP()             \
  X(radiance, __global float4*) SEP()                 \
  X(rays, __global uint*) SEP()                       \
  X(features, __global float4*)
// clang-format on

#define MR_ARG_COMMA() ,
#define MR_ARG_PARAM(name, type) type name
#define MR_ARG_INDEX(name, type) MR_ARG_##name
#define MR_ARG_NAME(name, type) #name

// Argument indices: MR_ARG_nodes = 0, ..., MR_ARG_COUNT.
enum RenderRectArg { MR_RENDER_RECT_ARGS(MR_ARG_INDEX, MR_ARG_COMMA), MR_ARG_COUNT };

#ifdef __cplusplus
inline constexpr const char* kRenderRectArgNames[] = {
    MR_RENDER_RECT_ARGS(MR_ARG_NAME, MR_ARG_COMMA)};
static_assert(sizeof(kRenderRectArgNames) / sizeof(kRenderRectArgNames[0]) == MR_ARG_COUNT);

static_assert(sizeof(LaunchParams) == 176);
static_assert(sizeof(CameraBlock) == 80);
static_assert(offsetof(LaunchParams, camera) == 0);
static_assert(offsetof(LaunchParams, env_choice_eps) == 80);
static_assert(offsetof(LaunchParams, rect) == 96);
static_assert(offsetof(LaunchParams, seed) == 112);
static_assert(offsetof(LaunchParams, width) == 120);
static_assert(offsetof(LaunchParams, spp) == 124);
static_assert(offsetof(LaunchParams, max_bounces) == 128);
static_assert(offsetof(LaunchParams, rr_start) == 132);
static_assert(offsetof(LaunchParams, frame) == 136);
static_assert(offsetof(LaunchParams, view) == 140);
static_assert(offsetof(LaunchParams, light_count) == 144);
static_assert(offsetof(LaunchParams, use_spp_map) == 148);
static_assert(offsetof(LaunchParams, has_tangents) == 152);
static_assert(offsetof(LaunchParams, cutouts) == 156);
static_assert(offsetof(LaunchParams, sample_clamp) == 160);
static_assert(offsetof(LaunchParams, first_sample) == 164);
static_assert(offsetof(LaunchParams, feature_buffers) == 168);
#endif

#ifdef __cplusplus
}  // namespace multiray
#endif

#endif  // MULTIRAY_DEVICE_OPENCL_KERNELS_LAUNCH_PARAMS_H
