// The records of the scene as the integrator reads them, one layout for every backend:
// the CPU keeps them in RenderScene (render/scene_records.cpp packs them), an OpenCL
// device uploads the same bytes. Only float arrays and 32-bit scalars, never float3 (16
// bytes in OpenCL C, 12 in C++), so both compilers lay them out alike; the sizes are
// checked on both sides below and the offsets by the C++ side (render/scene_records.cpp).
#ifndef MULTIRAY_RENDER_SHARED_SCENE_RECORDS_H
#define MULTIRAY_RENDER_SHARED_SCENE_RECORDS_H

#ifdef __cplusplus
#include "render/shared/language.h"
#endif

MR_NAMESPACE_BEGIN

// A Material (scene/scene.h) with its raw factors: the integrator multiplies them by
// their textures (render/shared/surface.h), then clamps them with bsdf_params.
typedef struct {
  float color[3];
  mr_int texture;  // base colour (sRGB, alpha = coverage) or -1
  float emission[3];
  mr_int emission_texture;  // or -1
  float metallic;
  float roughness;  // perceptual; GGX alpha = roughness^2
  float ior;        // > 1 (render/bsdf.h's material_ior)
  mr_uint dielectric;
  mr_uint emissive;                   // max component of emission > 0
  mr_int metallic_roughness_texture;  // G: roughness, B: metallic; or -1
  mr_int normal_texture;              // or -1
  float normal_scale;
  float opacity;
  mr_uint alpha_mode;  // AlphaMode: 0 opaque, 1 mask, 2 blend
  float alpha_cutoff;
  float pad;
} MaterialRecord;

// One emissive triangle of the LightSampler (render/lights.h), in its order.
typedef struct {
  float a[3];
  float pdf_area;  // selection probability / area
  float b[3];
  mr_uint prim;
  float c[3];
  float pad0;
  float radiance[3];  // the emission factor; the integrator applies the emission texture
  float pad1;
} LightRecord;

// A texture of the scene: where its texels start (an OpenCL device concatenates them;
// the CPU ignores the offset) and how its bytes decode (TexelCoding: 0 srgb, 1 linear,
// 2 signed_unit, the table of that index in the 3 x 256 decoding tables).
typedef struct {
  mr_uint offset;
  mr_int width;
  mr_int height;
  mr_uint coding;
} TextureRecord;

// The environment light (render/environment.h) and RenderScene::environment_choice(). The
// map's sampling tables live in one float array at the offsets given here; its radiance
// (3 floats a pixel, unscaled) in another, multiplied by map_scale when read.
typedef struct {
  float constant_sky[3];
  float choice;  // probability that next-event estimation picks the environment
  float frame_x[3];
  float sun_cos;
  float frame_up[3];
  float sun_pdf;
  float frame_z[3];
  float p_sun;
  float sun_dir[3];
  mr_uint sun_on;
  float sun_radiance[3];
  mr_uint sky_on;    // constant or map
  mr_int map_width;  // 0 x 0 without a map
  mr_int map_height;
  mr_uint on;       // EnvironmentLight::on()
  mr_uint row_cdf;  // offsets into the tables: height floats,
  mr_uint row_pdf;  // height floats,
  mr_uint col_cdf;  // width x height floats,
  mr_uint pix_pdf;  // width x height floats
  float map_scale;
} SkyRecord;

MR_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(multiray::MaterialRecord) == 80);
static_assert(sizeof(multiray::LightRecord) == 64);
static_assert(sizeof(multiray::TextureRecord) == 16);
static_assert(sizeof(multiray::SkyRecord) == 128);
#else
// OpenCL C 1.2 has no static_assert: an array of negative size stops the build instead.
typedef char mr_material_record_is_80_bytes[sizeof(MaterialRecord) == 80 ? 1 : -1];
typedef char mr_light_record_is_64_bytes[sizeof(LightRecord) == 64 ? 1 : -1];
typedef char mr_texture_record_is_16_bytes[sizeof(TextureRecord) == 16 ? 1 : -1];
typedef char mr_sky_record_is_128_bytes[sizeof(SkyRecord) == 128 ? 1 : -1];
#endif

#endif  // MULTIRAY_RENDER_SHARED_SCENE_RECORDS_H
