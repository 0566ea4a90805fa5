// The interface of the render_volume kernel (kernels/volume.cl), declared once for both
// sides as launch_params.h is for the path tracer (read its header comment: the same
// rules hold here). Embedded after launch_params.h, whose scalar typedefs and argument
// macros it uses; the host includes it from opencl_volume.cpp.
//
// VolumeParams: the scalars of one launch (camera, sampling keys) and of the frame's
// style and step, rewritten when it changes, as one small `__constant` buffer. No
// implicit padding, size a multiple of 16, no float3.
//
// MR_VOLUME_ARGS: every argument of render_volume in order, X(name, OpenCL C type),
// expanded into the kernel's parameter list and the host's indices (MR_VARG_<name>) and
// names (kVolumeArgNames).
#ifndef MULTIRAY_DEVICE_OPENCL_KERNELS_VOLUME_PARAMS_H
#define MULTIRAY_DEVICE_OPENCL_KERNELS_VOLUME_PARAMS_H

#if !defined(__OPENCL_C_VERSION__) && !defined(__OPENCL_VERSION__)
#include "device/opencl/kernels/launch_params.h"
#endif

#ifdef __cplusplus
namespace multiray {
#endif

// Byte offsets on the right.
typedef struct {
  CameraBlock camera;    //   0: PinholeCamera::block(), 80 bytes
  mr_float4 lower;       //  80: Volume::lower(), world units (w unused)
  mr_float4 spacing;     //  96: Volume::spacing, world units (w unused)
  mr_float4 background;  // 112: VolumeStyle::background (w unused)
  mr_int4 rect;          // 128: unused (zero): the rects are the `batch` argument's
  mr_int4 dims;          // 144: voxels per axis (w unused)
  mr_int4 blocks;        // 160: blocks per axis; w: 1 to skip blocks of opacity 0
  mr_ulong seed;         // 176
  mr_uint width;         // 184: of the view, in pixels
  mr_int spp;            // 188: samples per pixel when use_spp_map is 0
  mr_uint frame;         // 192
  mr_uint view;          // 196
  mr_int use_spp_map;    // 200: 1: spp_map[i] samples for work-item i
  mr_uint table_size;    // 204: entries of `table` (>= 2)
  float dt;              // 208: ray step in world units (step * step_scale * voxel length)
  float step_ratio;      // 212: step * step_scale / reference_step (opacity correction)
  float table_lo;        // 216: data value of table entry 0
  float table_to_index;  // 220: table entries per data unit
  float ert_threshold;   // 224: early ray termination at this opacity
  mr_uint first_sample;  // 228: ViewSetup::first_sample; `frame` is then the seed frame
  mr_uint pad[2];        // 232
} VolumeParams;          // 240

#ifdef MR_OPENCL_C
typedef char mr_volume_params_size_check[sizeof(VolumeParams) == 240 ? 1 : -1];
#endif

// clang-format off
#define MR_VOLUME_ARGS(X, SEP)                  \
  X(values, const __global float*) SEP()        \
  X(table, const __global float4*) SEP()        \
  X(block_opacity, const __global float*) SEP() \
  X(batch, const __global BatchRects*) SEP()    \
  X(params, __constant VolumeParams*) SEP()     \
  X(spp_map, const __global uchar*) SEP()       \
  X(radiance, __global float4*) SEP()           \
  X(steps, __global uint*)
// clang-format on

#define MR_VARG_INDEX(name, type) MR_VARG_##name

// Argument indices: MR_VARG_values = 0, ..., MR_VARG_COUNT.
enum VolumeArg { MR_VOLUME_ARGS(MR_VARG_INDEX, MR_ARG_COMMA), MR_VARG_COUNT };

#ifdef __cplusplus
inline constexpr const char* kVolumeArgNames[] = {MR_VOLUME_ARGS(MR_ARG_NAME, MR_ARG_COMMA)};
static_assert(sizeof(kVolumeArgNames) / sizeof(kVolumeArgNames[0]) == MR_VARG_COUNT);

static_assert(sizeof(VolumeParams) == 240);
static_assert(offsetof(VolumeParams, camera) == 0);
static_assert(offsetof(VolumeParams, lower) == 80);
static_assert(offsetof(VolumeParams, spacing) == 96);
static_assert(offsetof(VolumeParams, background) == 112);
static_assert(offsetof(VolumeParams, rect) == 128);
static_assert(offsetof(VolumeParams, dims) == 144);
static_assert(offsetof(VolumeParams, blocks) == 160);
static_assert(offsetof(VolumeParams, seed) == 176);
static_assert(offsetof(VolumeParams, width) == 184);
static_assert(offsetof(VolumeParams, spp) == 188);
static_assert(offsetof(VolumeParams, frame) == 192);
static_assert(offsetof(VolumeParams, view) == 196);
static_assert(offsetof(VolumeParams, use_spp_map) == 200);
static_assert(offsetof(VolumeParams, table_size) == 204);
static_assert(offsetof(VolumeParams, dt) == 208);
static_assert(offsetof(VolumeParams, step_ratio) == 212);
static_assert(offsetof(VolumeParams, table_lo) == 216);
static_assert(offsetof(VolumeParams, table_to_index) == 220);
static_assert(offsetof(VolumeParams, ert_threshold) == 224);
static_assert(offsetof(VolumeParams, first_sample) == 228);
static_assert(offsetof(VolumeParams, pad) == 232);
#endif

#ifdef __cplusplus
}  // namespace multiray
#endif

#endif  // MULTIRAY_DEVICE_OPENCL_KERNELS_VOLUME_PARAMS_H
