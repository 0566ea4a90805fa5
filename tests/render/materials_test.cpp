// Material textures and cut-outs against known answers, on a diffuse plane lit by a sun
// (radiance albedo / pi x E x cos between the shading normal and the sun).
#include <gtest/gtest.h>

#include <cmath>

#include "render/render_helpers.h"
#include "render/render_types.h"
#include "render/scene_records.h"
#include "render/shared/surface.h"
#include "render/surface.h"
#include "scene/builders.h"

namespace multiray {
namespace materials_test {

constexpr int kW = 16, kH = 16;
constexpr float kE = 3.0f;  // sun irradiance at normal incidence

// The lit plane (y = 0, facing +y, seen from above) with uv = (x, z) and a sun in
// direction `to_sun`, no sky.
Scene sunlit_plane(Vec3 to_sun) {
  Scene s = make_lit_plane(0.5f, 0.0f);
  for (const Vec3& p : s.positions) s.uvs.push_back({p.x, p.z});
  s.sun.direction = normalize(to_sun);
  const float sn = std::sin(s.sun.half_angle_rad);
  s.sun.radiance = Vec3(kE / (kPi * sn * sn));
  return s;
}

// A w x h texture of one pixel value.
Texture solid(unsigned char r, unsigned char g, unsigned char b, unsigned char a,
              TexelCoding coding, int w = 4, int h = 4) {
  std::vector<unsigned char> px;
  for (int i = 0; i < w * h; ++i) px.insert(px.end(), {r, g, b, a});
  return Texture::from_pixels(px.data(), w, h, 4, coding);
}

Framebuffer render(const Scene& scene, int spp = 4) {
  RenderSettings s;
  s.spp = spp;
  s.max_bounces = 2;
  return testing::render_regions(scene, kW, kH, s, {{0, 0, kW, kH}});
}

double mean_red(const Framebuffer& fb) {
  double sum = 0;
  for (const Vec3& p : fb.pixels) sum += p.x;
  return sum / double(fb.pixels.size());
}

// Texture rows follow v and columns u: texel row 0 is at v = 0 (glTF's convention; the OBJ
// loader turns OBJ's v = 0 at the bottom into it), so a texture can never be read upside
// down or mirrored without this failing (a flipped v once went unseen by every image test).
TEST(Texture, RowZeroIsVZeroAndColumnZeroIsUZero) {
  const unsigned char px[2 * 2 * 4] = {255, 255, 255, 255, 0,   0,   0,   255,   // white | black
                                       0,   0,   0,   255, 255, 255, 255, 255};  // black | white
  const Texture tex = Texture::from_pixels(px, 2, 2, 4);
  const TextureView view = texture_view(tex);
  const auto sample = [&](Vec2 uv) { return texture_sample(&view, uv); };
  EXPECT_NEAR(sample({0.25f, 0.25f}).x, 1.0f, 1e-5f);  // texel (0, 0): white
  EXPECT_NEAR(sample({0.75f, 0.25f}).x, 0.0f, 1e-5f);  // texel (1, 0)
  EXPECT_NEAR(sample({0.25f, 0.75f}).x, 0.0f, 1e-5f);  // texel (0, 1)
  EXPECT_NEAR(sample({0.75f, 0.75f}).x, 1.0f, 1e-5f);  // texel (1, 1): white
}

// A flat normal map (128, 128, 255) leaves the image exactly as without one.
TEST(NormalMap, FlatMapEqualsThePlainPlane) {
  Scene plain = sunlit_plane({1, 2, 0.5f}), mapped = plain;
  mapped.textures.push_back(solid(128, 128, 255, 255, TexelCoding::signed_unit));
  mapped.materials[0].normal_texture = 0;
  const Framebuffer a = render(plain), b = render(mapped);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(a.pixels[i][c], b.pixels[i][c]) << i;
}

// A map tilted along the tangent (+x, the direction of +u) or the bitangent (-z, glTF's
// +y of the map, since v = z grows down the image) turns the shading normal; the plane's
// radiance follows the cosine with the tilted normal, and a tilt away from the sun darkens.
TEST(NormalMap, TiltFollowsTangentFrameAndCosine) {
  const float* dec = texel_decoding_table(TexelCoding::signed_unit);
  const unsigned char bx = 128 + 64, bz = 128 + 110;            // about 30 degrees of tilt
  const Vec3 tilt_x = normalize(Vec3(dec[bx], dec[bz], 0.0f));  // (tangent, normal) plane
  struct Case {
    unsigned char r, g;
    Vec3 to_sun, normal;
  };
  const Vec3 sun_x = normalize(Vec3(1, 1, 0)), sun_mz = normalize(Vec3(0, 1, -1));
  const Case cases[] = {
      {bx, 128, sun_x, Vec3(tilt_x.x, tilt_x.y, 0)},    // towards the sun along +u
      {128, bx, sun_mz, Vec3(0, tilt_x.y, -tilt_x.x)},  // towards the sun along -v
      {128, bx, sun_x, Vec3(0, tilt_x.y, -tilt_x.x)},   // across the sun: cos drops
  };
  for (const Case& c : cases) {
    Scene s = sunlit_plane(c.to_sun);
    s.textures.push_back(solid(c.r, c.g, bz, 255, TexelCoding::signed_unit));
    s.materials[0].normal_texture = 0;
    const double expected = 0.5 / kPi * kE * std::max(0.0f, dot(c.normal, normalize(c.to_sun)));
    EXPECT_NEAR(mean_red(render(s)), expected, 0.01 * expected) << int(c.r) << "," << int(c.g);
  }
}

// Emission through a texture: seen directly, each half of the quad shows factor x texel.
TEST(EmissionTexture, SeenDirectlyPerTexel) {
  Scene s = make_lit_plane(0.0f, 0.0f);
  for (const Vec3& p : s.positions) s.uvs.push_back({p.x / 4.0f + 0.5f, 0.5f});
  unsigned char px[2 * 4] = {255, 255, 255, 255, 0, 0, 0, 255};  // white | black
  s.textures.push_back(Texture::from_pixels(px, 2, 1, 4));
  s.materials[0].emission = Vec3(2.0f);
  s.materials[0].emission_texture = 0;
  s.cameras[0].fov_y_deg = 30.0f;  // sees x in about [-0.27, 0.27]: the middle texels
  const Framebuffer fb = render(s, 1);
  // Nearest texel centres are at u = 0.25 (white) and 0.75 (black); bilinear between.
  for (int y = 0; y < kH; ++y) {
    EXPECT_GT(fb.at(1, y).x, fb.at(kW - 2, y).x);
    EXPECT_LE(fb.at(1, y).x, 2.0f + 1e-5f);
    EXPECT_GE(fb.at(kW - 2, y).x, 0.0f);
  }
}

// Light from a textured emitter, sampled by next-event estimation with the texel's
// radiance: the same mean as an untextured emitter of the texture's colour.
TEST(EmissionTexture, LightsTheSceneAsItsTexels) {
  auto scene_with = [](bool textured) {
    Scene s = make_lit_plane(0.5f, 0.0f);
    s.uvs.assign(s.positions.size(), {0.5f, 0.5f});
    const float* srgb = texel_decoding_table(TexelCoding::srgb);
    const uint32_t light =
        add_material(s, Material{.name = "light",
                                 .base_color = Vec3(0.0f),
                                 .emission = textured ? Vec3(4.0f) : Vec3(4.0f * srgb[180])});
    add_quad(s, {-1, 3, -1}, {1, 3, -1}, {1, 3, 1}, {-1, 3, 1}, light);  // faces down
    while (s.uvs.size() < s.positions.size()) s.uvs.push_back({0.5f, 0.5f});
    if (textured) {
      s.textures.push_back(solid(180, 180, 180, 255, TexelCoding::srgb));
      s.materials[light].emission_texture = 0;
    }
    return s;
  };
  const double plain = mean_red(render(scene_with(false), 32));
  const double textured = mean_red(render(scene_with(true), 32));
  EXPECT_GT(plain, 0.0);
  EXPECT_NEAR(textured, plain, 0.02 * plain);
}

// Metallic-roughness: G scales roughness, B scales metallic, both linear.
TEST(MetallicRoughness, TextureScalesTheFactors) {
  Scene s = make_lit_plane(0.5f, 0.0f);
  s.textures.push_back(solid(0, 128, 255, 255, TexelCoding::linear));
  s.materials[0].metallic = 0.5f, s.materials[0].roughness = 0.8f;
  s.materials[0].metallic_roughness_texture = 0;
  const RenderScene rs(s);
  const SceneData sd = rs.scene_data(0.0f, 1e-4f);
  const SurfacePoint sp =
      surface_at(&sd, &rs.materials[0], {0.3f, 0.6f}, Vec3(0, 1, 0), Vec3(0, 1, 0), 0, nullptr);
  EXPECT_NEAR(sp.roughness, 0.8f * 128.0f / 255.0f, 1e-5f);
  EXPECT_NEAR(sp.metallic, 0.5f, 1e-5f);
}

// A cut-out occluder between the sun and the plane. Mask with alpha 0 everywhere: not there
// at all (bit-identical image). Opaque: a full shadow. Blend with opacity 1/2: half the sun.
TEST(AlphaModes, MaskDropsAndBlendHalvesTheShadow) {
  Scene open = sunlit_plane({0, 1, 0});
  auto with_occluder = [&](AlphaMode mode, float opacity, unsigned char alpha) {
    Scene s = open;
    const uint32_t m =
        add_material(s, Material{.name = "leaf", .opacity = opacity, .alpha_mode = mode});
    add_quad(s, {-5, 0.5f, -5}, {-5, 0.5f, 5}, {5, 0.5f, 5}, {5, 0.5f, -5}, m);
    while (s.uvs.size() < s.positions.size()) s.uvs.push_back({0.5f, 0.5f});
    s.textures.push_back(solid(255, 255, 255, alpha, TexelCoding::srgb));
    s.materials[m].base_color_texture = 0;
    return s;
  };
  const Framebuffer lit = render(open);
  const Framebuffer gone = render(with_occluder(AlphaMode::mask, 1.0f, 0));
  for (size_t i = 0; i < lit.pixels.size(); ++i) ASSERT_EQ(lit.pixels[i].x, gone.pixels[i].x);
  // Camera at y = 1 looks down through the occluder at y = 0.5: an opaque one fills the
  // view (its top is lit: 0.8 albedo), a mask at alpha 1 is opaque too.
  const double full = mean_red(lit);
  const double opaque_mask = mean_red(render(with_occluder(AlphaMode::mask, 1.0f, 255)));
  EXPECT_NEAR(opaque_mask, 0.8 / kPi * kE, 0.01 * 0.8 / kPi * kE);
  // Blend at 1/2: half the camera rays see the plane (half shadowed), half the occluder.
  const double blend = mean_red(render(with_occluder(AlphaMode::blend, 0.5f, 255), 64));
  const double expected = 0.5 * (0.8 / kPi * kE) + 0.5 * (0.5 * full);
  EXPECT_NEAR(blend, expected, 0.03 * expected);
}

// A smooth glass pane between the camera and a glowing floor lets the floor's light
// through: Fresnel reflects about 4% at each face (ior 1.5, near normal incidence), and the
// compression of radiance entering the glass is undone leaving it, so the floor's radiance
// 1 arrives as about 0.92. A pane that only reflected would show the black sky (~0).
TEST(Glass, ASmoothPaneLetsTheLightBehindItThrough) {
  Scene s = make_lit_plane(0.5f, 0.0f);
  s.materials[0].emission = Vec3(1.0f);
  const uint32_t glass = add_material(
      s, Material{.name = "glass", .roughness = 0.05f, .transmission = 1.0f, .ior = 1.5f});
  add_box(s, {0, 0.5f, 0}, {50, 0.05f, 50}, 0.0f, glass);
  const double mean = mean_red(render(s, 16));
  EXPECT_GT(mean, 0.88);
  EXPECT_LT(mean, 0.96);
}

}  // namespace materials_test
}  // namespace multiray
