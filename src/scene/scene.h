// The scene every device renders: one flat triangle soup with per-triangle materials.
// Node hierarchies and instances are baked into world space by the loaders, so the
// CPU (Embree) and OpenCL backends see the same simple arrays. Built once, read-only
// while rendering.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"

namespace multiray {

struct Volume;  // volume/volume.h

// How a texture's bytes turn into numbers when sampled.
// - srgb: colour (base colour, emission), decoded by the sRGB curve to linear RGB.
// - linear: data in [0, 1] (metallic-roughness), byte / 255.
// - signed_unit: tangent-space normals in [-1, 1]. Byte 128 is exactly 0 (bytes above map
//   onto (0, 1] by / 127, below onto [-1, 0) by / 128), so a flat map (128, 128, 255)
//   leaves the shading normal exactly as it was; byte * 2 / 255 - 1 would tilt it by 0.2°.
enum class TexelCoding : uint8_t { srgb, linear, signed_unit };

// A texture, wrapped (repeat) and bilinearly filtered. Texels stay 8-bit (decoded through
// a table when sampled): a third of the memory of float texels, which matters because
// texture cache misses dominated shading time. Alpha is always linear (byte / 255).
struct Texture {
  int width = 0, height = 0;
  TexelCoding coding = TexelCoding::srgb;
  std::vector<uint32_t> texels;  // row-major, v = 0 at the top row; R | G<<8 | B<<16 | A<<24

  // From 8-bit pixels with 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA) channels;
  // alpha is 255 where the pixels have none.
  static Texture from_pixels(const unsigned char* pixels, int width, int height, int channels,
                             TexelCoding coding = TexelCoding::srgb);
  Vec3 texel(int x, int y) const;  // decoded RGB
  // Sampling (wrapped, bilinear) is render/shared/texture.h's, written once for the CPU
  // and the OpenCL kernels; render/scene_records.h's texture_view() makes its view.
  // Whether some texel's alpha is below 255.
  bool has_alpha() const;
  bool empty() const { return width <= 0 || height <= 0; }
};

// The decoding table of `coding`: linear value of each byte (core of texture sampling,
// render/shared/texture.h; the OpenCL backend uploads the same tables so both decode bytes
// identically).
const float* texel_decoding_table(TexelCoding coding);

// glTF's alpha modes: opaque ignores alpha; mask keeps a surface point when its alpha is
// at least `alpha_cutoff`; blend keeps it with probability alpha (stochastic
// transparency, the same decision for the same ray on every device).
enum class AlphaMode : uint8_t { opaque, mask, blend };

// One material model for every loader (glTF 2.0 metallic-roughness and its common
// extensions):
// - transmission > 0: rough dielectric (GGX) with index `ior`;
// - otherwise a stochastic mix: conductor (GGX, F0 = base colour) with probability
//   `metallic`, Lambertian diffuse with `base_color` otherwise.
// `emission` (radiance, W/(sr m^2) in scene units) makes every triangle using it an
// area light. Each factor is multiplied by its texture, when there is one, per texel.
// glTF's occlusion texture is deliberately not read: it approximates the indirect
// shadowing a path tracer computes (Blender Cycles ignores it the same way).
struct Material {
  std::string name;
  Vec3 base_color{0.8f, 0.8f, 0.8f};
  int base_color_texture = -1;  // index into Scene::textures or -1; sRGB, alpha = coverage
  Vec3 emission{0, 0, 0};
  int emission_texture = -1;  // sRGB, multiplies `emission`
  float metallic = 0.0f;
  float roughness = 1.0f;               // perceptual roughness; GGX alpha = roughness^2
  int metallic_roughness_texture = -1;  // linear: G multiplies roughness, B metallic
  int normal_texture = -1;              // signed_unit, tangent space (+x = +u, +y = -v)
  float normal_scale = 1.0f;            // scales the map's x and y
  float opacity = 1.0f;                 // base colour alpha factor, [0, 1]
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;  // mask mode only
  float transmission = 0.0f;
  float ior = 1.5f;

  // Whether some point of a triangle with this material may be skipped by rays.
  bool may_be_transparent() const { return alpha_mode != AlphaMode::opaque; }
};

// Pinhole camera. `fov_y_deg` is the full vertical field of view.
struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  float fov_y_deg = 45.0f;
  // The image size the scene file asks for (a Mitsuba film), or 0 x 0 when it names none.
  // fov_y_deg was derived with this aspect ratio.
  int film_width = 0, film_height = 0;
};

// The default camera's view direction, degrees: round the up axis from the front towards
// the right, and above the horizon.
constexpr float kDefaultAzimuthDeg = 35.0f;
constexpr float kDefaultElevationDeg = 25.0f;
constexpr float kDefaultFovDeg = 45.0f;
// Fraction of each half of the image the projected bounds may fill.
constexpr float kDefaultMargin = 0.92f;

// An equirectangular (latitude-longitude) radiance map around the scene. Row 0 looks
// along the scene's up axis, the last row down; the middle column looks along the front
// (environment_frame() in render/environment.h fixes the axes).
struct EnvironmentMap {
  std::string name;  // file name, for messages and stats
  int width = 0, height = 0;
  std::vector<Vec3> radiance;  // row-major, linear RGB, finite and >= 0
};

// A distant disc light: `direction` points from the scene towards the sun (unit),
// `radiance` is constant over the disc of angular radius `half_angle_rad`. Off while
// radiance is zero.
struct Sun {
  Vec3 direction{0, 1, 0};
  Vec3 radiance{0, 0, 0};
  float half_angle_rad = 0.00465f;  // the real sun: 0.53 degrees across
  bool on() const { return max_component(radiance) > 0; }
};

struct Scene {
  std::string name;  // file name or "cornell-box"
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;           // empty, or one per position (shading normals)
  std::vector<Vec2> uvs;               // empty, or one per position
  std::vector<uint32_t> indices;       // three per triangle, into positions
  std::vector<uint32_t> material_ids;  // one per triangle, into materials
  std::vector<Material> materials;
  std::vector<Texture> textures;
  Vec3 environment{0, 0, 0};  // constant radiance of rays that leave the scene
  // Added to `environment` when set (--env FILE), scaled by environment_map_scale.
  std::shared_ptr<const EnvironmentMap> environment_map;
  float environment_map_scale = 1.0f;
  Vec3 up{0, 1, 0};  // the world axis the environment map and the sun take as up
  Sun sun;
  std::vector<Camera> cameras;  // cameras found in the file (may be empty)
  // The up axis the file declares (a signed world axis) for --up auto, or zero where its
  // format says nothing; `file_up_from` names what said it (for the note). Only FBX does,
  // among the formats read: glTF is Y-up by definition and assimp already turns COLLADA's
  // <up_axis> into Y-up (scene/load_assimp.cpp).
  Vec3 file_up{0, 0, 0};
  std::string file_up_from;
  // A volume for the raycaster (kernel "volume"), or null. A scene read from a volume file
  // has a volume and no triangles; mesh kernels refuse it and the volume kernel refuses a
  // scene without one.
  std::shared_ptr<const Volume> volume;

  size_t triangle_count() const { return indices.size() / 3; }
  bool has_triangles() const { return !indices.empty(); }
  // The triangles' bounds, or the volume's box for a volume scene.
  Bounds3 bounds() const;
  // A camera outside the scene's bounds that frames all of them, looking at their centre
  // from `azimuth_deg` round the up axis from the front towards the right and
  // `elevation_deg` above (default: a three-quarter view), at the distance where every
  // corner of bounds() projects inside an image of width/height `aspect` with
  // kDefaultMargin of it to spare. `up` is the world axis the scene calls up
  // (up_axis_vector); the front is the axis glTF's convention makes it for +y (+z),
  // Blender's for +z (-y). render/default_view.h picks among such views for meshes.
  Camera default_camera(float aspect, Vec3 up = Vec3(0, 1, 0),
                        float azimuth_deg = kDefaultAzimuthDeg,
                        float elevation_deg = kDefaultElevationDeg) const;
};

// Unit direction `azimuth_deg` round the up axis `up` (a signed world axis) from the front
// towards the right and `elevation_deg` above the horizon; the front is the axis glTF's
// convention makes it for +y (+z), Blender's for +z (-y). The default camera looks from
// here at the scene, and --sun places the sun here.
Vec3 view_direction(Vec3 up, float azimuth_deg, float elevation_deg);

// The unit world axis named by `name`: x, y, z with an optional sign (+x, -z, ...).
// Returns false for anything else.
bool up_axis_vector(const std::string& name, Vec3& up);

// The up axis of FBX's GlobalSettings (as assimp's scene metadata passes them on):
// `up_axis` 0, 1, 2 for x, y, z and `up_axis_sign` +1 or -1. Returns false for anything
// else (the file is then taken to say nothing).
bool fbx_up_axis(int up_axis, int up_axis_sign, Vec3& up);

// Largest coordinate magnitude of a scene vertex, scene units. Keeps the scene's bounds,
// their extent and the products Embree forms from them finite in float (max ~3.4e38);
// the same limit as for cameras (kMaxCameraCoordinate).
constexpr float kMaxSceneCoordinate = 1e18f;

// Checks the invariants every backend relies on and throws InputError naming the first
// violation: indices in range, finite positions/normals/uvs, positions within
// kMaxSceneCoordinate, material ids in range, attribute arrays of matching size, at least
// one triangle of non-zero area unless the scene is a volume (then no triangles at all).
// Degenerate (zero-area) triangles are allowed; they are never hit.
void validate(const Scene& scene);

}  // namespace multiray
