// The scene's records as the integrator reads them (render/shared/scene_records.h), made
// from scene/scene.h's types once per scene: the CPU keeps them in RenderScene, an OpenCL
// device uploads the same bytes (device/gpu_scene/scene_buffers.cpp).
#pragma once

#include "render/shared/scene_records.h"
#include "render/shared/texture.h"
#include "scene/scene.h"

namespace multiray {

// `m` with the BSDF's choices that no texture changes (render/bsdf.h) made once.
MaterialRecord material_record(const Material& m);

// `t` as the shared texture functions read it (pointing into t's texels).
TextureView texture_view(const Texture& t);

}  // namespace multiray
