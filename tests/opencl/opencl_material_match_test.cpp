// The OpenCL image against the CPU's for per-texel materials (render/surface.h): emission,
// metallic-roughness and normal textures, texel codings and alpha cut-outs, each by the
// z-test of opencl_ztest.h with its power shown (the CPU image of the scene without the
// feature fails the same test), and all at once with the same seed.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "opencl_ztest.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_material_match_test {

using testing::expect_matches_cpu;
using testing::expect_test_sees_feature;

// A 4 x 4 texture of RGBA texels repeating `pattern` (4 bytes each) row by row.
Texture pattern_texture(std::initializer_list<std::array<unsigned char, 4>> pattern,
                        TexelCoding coding) {
  std::vector<unsigned char> px;
  for (int i = 0; i < 16; ++i) {
    const auto& p = *(pattern.begin() + (i + i / 4) % int(pattern.size()));
    px.insert(px.end(), p.begin(), p.end());
  }
  return Texture::from_pixels(px.data(), 4, 4, 4, coding);
}

// The Cornell box with uvs that vary over every wall (none degenerate, so every triangle
// has a tangent frame) and a dim sky seen through the open front.
Scene textured_box(const std::string& name) {
  Scene s = make_cornell_box();
  s.name = name;
  for (const Vec3& p : s.positions)
    s.uvs.push_back({1.3f * p.x + 0.7f * p.z, 1.1f * p.y + 0.4f * p.z});
  s.environment = Vec3(0.3f);
  return s;
}

Material& material(Scene& s, const std::string& name) {
  for (Material& m : s.materials)
    if (m.name == name) return m;
  throw std::logic_error("no material " + name);
}

int add_texture(Scene& s, Texture t) {
  s.textures.push_back(std::move(t));
  return int(s.textures.size()) - 1;
}

// The ceiling light's emission through a colour checker with a black texel: the light
// sample's radiance is the texel's, the LightSampler's power estimate picks triangles.
Scene emission_scene() {
  Scene s = textured_box("box-emission-texture");
  material(s, "light").emission_texture = add_texture(
      s,
      pattern_texture({{255, 255, 255, 255}, {255, 60, 20, 255}, {0, 0, 0, 255}, {0, 0, 0, 255}},
                      TexelCoding::srgb));
  return s;
}

// White surfaces become fully metallic and rough, then the texture's G scales roughness
// and B metallic per texel (linear bytes).
Scene metallic_roughness_scene() {
  Scene s = textured_box("box-metallic-roughness");
  Material& w = material(s, "white");
  w.metallic = 1.0f, w.roughness = 1.0f;
  w.metallic_roughness_texture =
      add_texture(s, pattern_texture({{0, 40, 255, 255}, {0, 230, 0, 255}, {0, 120, 160, 255}},
                                     TexelCoding::linear));
  return s;
}

// The green wall's base colour from bytes decoded as linear, not sRGB.
Scene coding_scene(TexelCoding coding) {
  Scene s = textured_box("box-linear-base-colour");
  material(s, "green").base_color = Vec3(1.0f);
  material(s, "green").base_color_texture =
      add_texture(s, pattern_texture({{40, 160, 60, 255}, {120, 40, 200, 255}}, coding));
  return s;
}

// Tilts of about 50 degrees in four directions over a smooth sphere lit by one small
// light and a dim sky (the Cornell box's noise would hide them), uvs projected from a
// plane so that every triangle has a tangent frame.
Scene normal_map_scene() {
  Scene s = make_lit_sphere(0.8f, 12, 24, true);
  s.name = "sphere-normal-map";
  for (const Vec3& p : s.positions)
    s.uvs.push_back({1.3f * p.x + 0.7f * p.z, 1.1f * p.y + 0.4f * p.z});
  s.environment = Vec3(0.1f);
  material(s, "sphere").normal_texture = add_texture(
      s,
      pattern_texture(
          {{240, 128, 180, 255}, {128, 20, 180, 255}, {20, 128, 180, 255}, {128, 240, 180, 255}},
          TexelCoding::signed_unit));
  return s;
}

// The red wall cut out by its base colour alpha (mask), the green one half transparent
// (blend), both for camera and shadow rays.
Scene alpha_scene() {
  Scene s = textured_box("box-alpha");
  Material& red = material(s, "red");
  red.base_color = Vec3(1.0f);
  red.base_color_texture =
      add_texture(s, pattern_texture({{160, 20, 20, 255}, {160, 20, 20, 0}, {200, 60, 20, 100}},
                                     TexelCoding::srgb));
  red.alpha_mode = AlphaMode::mask;
  material(s, "green").alpha_mode = AlphaMode::blend;
  material(s, "green").opacity = 0.45f;
  return s;
}

Scene without(Scene s, void (*strip)(Material&)) {
  for (Material& m : s.materials) strip(m);
  return s;
}

TEST(OpenClMaterialMatch, EmissionTextureMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = emission_scene();
  expect_matches_cpu(with, 8);
  expect_test_sees_feature(with, without(with, [](Material& m) { m.emission_texture = -1; }), 8);
}

TEST(OpenClMaterialMatch, MetallicRoughnessTextureMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = metallic_roughness_scene();
  expect_matches_cpu(with, 8);
  expect_test_sees_feature(
      with, without(with, [](Material& m) { m.metallic_roughness_texture = -1; }), 8);
}

// Power: the same bytes decoded as sRGB.
TEST(OpenClMaterialMatch, TexelCodingMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = coding_scene(TexelCoding::linear);
  expect_matches_cpu(with, 8);
  Scene srgb = coding_scene(TexelCoding::srgb);
  srgb.name = with.name;
  expect_test_sees_feature(with, srgb, 8);
}

TEST(OpenClMaterialMatch, NormalMapMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = normal_map_scene();
  expect_matches_cpu(with, 8);
  expect_test_sees_feature(with, without(with, [](Material& m) { m.normal_texture = -1; }), 8);
}

TEST(OpenClMaterialMatch, AlphaCutoutsMatchCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = alpha_scene();
  expect_matches_cpu(with, 8);
  expect_test_sees_feature(
      with, without(with, [](Material& m) { m.alpha_mode = AlphaMode::opaque; }), 8);
}

// Every feature at once, and each alone, with the same seed: the kernel draws the CPU's
// random numbers in the CPU's order, so nearly every channel equals the CPU's to float
// rounding. Blend is left out: its decision hashes the ray's bits, and a secondary ray
// starts at a hit distance that Embree and the kernel compute an ulp apart, so the same
// ray gets another hash (camera rays, computed alike, do agree); the mask decisions
// agree except at the cutoff's contour.
TEST(OpenClMaterialMatch, SameSeedWithEveryMaterialFeatureGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = alpha_scene();
  scene.name = "box-every-material-feature";
  material(scene, "green").alpha_mode = AlphaMode::opaque;
  const Scene e = emission_scene(), mr = metallic_roughness_scene(), nm = normal_map_scene();
  const int offset = int(scene.textures.size());
  scene.textures.push_back(e.textures[0]);
  scene.textures.push_back(mr.textures[0]);
  scene.textures.push_back(nm.textures[0]);
  material(scene, "light").emission_texture = offset;
  Material& w = material(scene, "white");
  w.metallic = 1.0f, w.roughness = 1.0f;
  w.metallic_roughness_texture = offset + 1;
  w.normal_texture = offset + 2;
  EXPECT_GE(testing::same_seed_agreement(scene), 0.9);
  for (const Scene& one : {emission_scene(), metallic_roughness_scene(), normal_map_scene(),
                           coding_scene(TexelCoding::linear)})
    EXPECT_GE(testing::same_seed_agreement(one), 0.9);
}

}  // namespace opencl_material_match_test
}  // namespace multiray
