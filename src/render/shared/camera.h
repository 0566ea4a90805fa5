// The pinhole camera's primary rays, one definition for the CPU's PinholeCamera
// (render/path_tracer.h) and the OpenCL programs, and the camera block that opens both
// OpenCL parameter blocks (launch_params.h, volume_params.h). Written in
// render/shared/language.h's dialect.
#ifndef MULTIRAY_RENDER_SHARED_CAMERA_H
#define MULTIRAY_RENDER_SHARED_CAMERA_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// PinholeCamera's frame: the eye, then the unit vectors forward, right and up (w unused),
// and scale = (tan half-fov x, tan half-fov y, 2 / view width, 2 / view height), the
// last two in 1 / pixels. 80 bytes, every member at a multiple of 16, no implicit
// padding: the host writes it into the OpenCL parameter blocks as it is.
typedef struct {
  mr_float4 eye;      //  0
  mr_float4 forward;  // 16
  mr_float4 right;    // 32
  mr_float4 up;       // 48
  mr_float4 scale;    // 64
} CameraBlock;        // 80

// Unit direction of the primary ray through image position (px, py), in pixels
// (fractional; x right, y down; (0, 0) is the top-left corner of the view).
MR_DEVICE mr_float3 camera_dir(const CameraBlock* c, float px, float py) {
  const float sx = (px * c->scale.z - 1.0f) * c->scale.x;
  const float sy = (1.0f - py * c->scale.w) * c->scale.y;
  return normalize3(MR_XYZ(c->forward) + MR_XYZ(c->right) * sx + MR_XYZ(c->up) * sy);
}

MR_NAMESPACE_END

#endif  // MULTIRAY_RENDER_SHARED_CAMERA_H
