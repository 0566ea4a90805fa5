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

// Colour texture, wrapped (repeat) and bilinearly filtered; lookups return linear RGB.
// Texels stay 8-bit sRGB (decoded through a table when sampled): a third of the memory
// of float texels, which matters because texture cache misses dominated shading time.
struct Texture {
  int width = 0, height = 0;
  std::vector<uint32_t> srgb8;  // row-major, v = 0 at the top row; R | G << 8 | B << 16

  // From 8-bit sRGB pixels with 1 (grey) or >= 3 channels (extra channels ignored).
  static Texture from_srgb8(const unsigned char* pixels, int width, int height, int channels);
  Vec3 texel(int x, int y) const;  // linear RGB
  Vec3 sample(Vec2 uv) const;
  // Asks the CPU to start loading the texels sample(uv) will read (a hint; no effect on
  // results).
  void prefetch(Vec2 uv) const;

 private:
  // The top-left texel of the bilinear footprint of `uv`, wrapped into the texture.
  void footprint(Vec2 uv, int& x0, int& y0, float& tx, float& ty) const;
};

// One material model for every loader (a subset of glTF's metallic-roughness):
// - transmission > 0: rough dielectric (GGX) with index `ior`;
// - otherwise a stochastic mix: conductor (GGX, F0 = base colour) with probability
//   `metallic`, Lambertian diffuse with `base_color` otherwise.
// `emission` (radiance, W/(sr m^2) in scene units) makes every triangle using it an
// area light.
struct Material {
  std::string name;
  Vec3 base_color{0.8f, 0.8f, 0.8f};
  int base_color_texture = -1;  // index into Scene::textures or -1
  Vec3 emission{0, 0, 0};
  float metallic = 0.0f;
  float roughness = 1.0f;  // perceptual roughness; GGX alpha = roughness^2
  float transmission = 0.0f;
  float ior = 1.5f;
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

struct Scene {
  std::string name;  // file name or "cornell-box"
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;           // empty, or one per position (shading normals)
  std::vector<Vec2> uvs;               // empty, or one per position
  std::vector<uint32_t> indices;       // three per triangle, into positions
  std::vector<uint32_t> material_ids;  // one per triangle, into materials
  std::vector<Material> materials;
  std::vector<Texture> textures;
  Vec3 environment{0, 0, 0};    // constant radiance of rays that leave the scene
  std::vector<Camera> cameras;  // cameras found in the file (may be empty)
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

// The unit world axis named by `name`: x, y, z with an optional sign (+x, -z, ...).
// Returns false for anything else.
bool up_axis_vector(const std::string& name, Vec3& up);

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
