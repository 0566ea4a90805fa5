// The shadow catcher (render/shadow_catcher.h) against known answers: the occlusion a
// sphere casts on a plane under a constant sky, and pixels no object touches.
#include <gtest/gtest.h>

#include "core/image.h"
#include "render/shadow_catcher.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace shadow_catcher_test {

constexpr float kRadius = 0.5f, kHeight = 2.0f;

// A black sphere of radius kRadius centred kHeight above the catcher y = 0, a constant sky
// of radiance 1, and `camera`.
Scene sphere_over_ground(const Camera& camera, float sphere_y = kHeight) {
  Scene s;
  s.name = "sphere-over-ground";
  const uint32_t black = add_material(s, Material{.name = "black", .base_color = Vec3(0.0f)});
  add_sphere(s, {0, sphere_y, 0}, kRadius, 48, 96, false, black);
  s.environment = Vec3(1.0f);
  s.cameras.push_back(camera);
  return s;
}

RenderSettings catcher_settings(int spp) {
  RenderSettings s;
  s.spp = spp;
  s.catcher_axis = 1, s.catcher_height = 0.0f, s.catcher_albedo = 0.5f;
  return s;
}

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

float alpha_at(const Framebuffer& fb, int x, int y) {
  return fb.alpha.at(size_t(y) * size_t(fb.width) + size_t(x));
}

// Right below the sphere's centre the sphere fills a cone of half-angle asin(r / h) around
// the plane's normal, which carries (r / h)^2 of the cosine-weighted sky: the catcher keeps
// 1 - (r / h)^2 of its light. The camera looks at that point from 30 degrees above the
// plane, past the sphere (the line of sight passes 1.7 from its centre).
TEST(ShadowCatcher, ShadowRatioMatchesTheSpheresOcclusion) {
  const Vec3 dir = normalize(Vec3(std::cos(0.5236f), std::sin(0.5236f), 0.0f));
  const Scene scene = sphere_over_ground(Camera{dir * 4.0f, {0, 0, 0}, {0, 1, 0}, 4.0f});
  const int n = 9;
  const Framebuffer fb =
      testing::render_regions(scene, n, n, catcher_settings(1024), {{0, 0, n, n}}, 1, 2);
  ASSERT_EQ(fb.alpha.size(), fb.pixels.size());
  double kept = 0;
  for (int y = 3; y < 6; ++y)
    for (int x = 3; x < 6; ++x) kept += (1.0 - alpha_at(fb, x, y)) / 9.0;
  const double expected = 1.0 - (kRadius / kHeight) * (kRadius / kHeight);
  EXPECT_NEAR(kept, expected, 0.02 * expected);
  // Far from the shadow's centre the ground keeps more of its light.
  EXPECT_GT(1.0 - alpha_at(fb, 0, 0), kept);
  // The catcher shows no colour of its own: the layer's colour is the objects'.
  for (const Vec3& p : fb.pixels) EXPECT_TRUE(same(p, Vec3(0.0f)));
}

// The sphere seen against the sky: covered pixels are opaque and carry its radiance; sky
// pixels are transparent, bit for bit.
TEST(ShadowCatcher, ObjectsAreOpaqueAndTheSkyIsTransparent) {
  Scene scene = sphere_over_ground(Camera{{0, 2, 6}, {0, 2, 0}, {0, 1, 0}, 30.0f});
  scene.materials[0].base_color = Vec3(0.5f);
  const int w = 32, h = 32;
  const Framebuffer fb =
      testing::render_regions(scene, w, h, catcher_settings(16), {{0, 0, w, h}}, 1, 2);
  EXPECT_EQ(alpha_at(fb, w / 2, h / 2), 1.0f);
  EXPECT_GT(fb.at(w / 2, h / 2).y, 0.1f);
  EXPECT_EQ(alpha_at(fb, 0, 0), 0.0f);
  EXPECT_TRUE(same(fb.at(0, 0), Vec3(0.0f)));
}

// Ground that no object can shadow (the sphere is below the plane, hidden by it) keeps
// exactly its real colour: every catcher sample's two estimates are the same number.
TEST(ShadowCatcher, UnshadowedGroundIsLeftExactlyAsItWas) {
  const Scene scene = sphere_over_ground(Camera{{0, 3, 6}, {0, 0, 0}, {0, 1, 0}, 60.0f}, -5.0f);
  const int w = 24, h = 16;
  const Framebuffer fb =
      testing::render_regions(scene, w, h, catcher_settings(8), {{0, 0, w, h}}, 1, 2);
  for (float a : fb.alpha) ASSERT_EQ(a, 0.0f);
}

// The layer does not depend on how the frame was split or how many devices shared it.
TEST(ShadowCatcher, LayerIsTheSameHoweverTheFrameIsSplit) {
  const Scene scene = sphere_over_ground(Camera{{3, 3, 5}, {0, 1, 0}, {0, 1, 0}, 50.0f});
  const int w = 40, h = 24;
  const RenderSettings s = catcher_settings(4);
  const Framebuffer whole = testing::render_regions(scene, w, h, s, {{0, 0, w, h}});
  const Framebuffer split =
      testing::render_regions(scene, w, h, s, {{0, 0, 13, h}, {13, 0, w, 7}, {13, 7, w, h}}, 2, 1);
  EXPECT_EQ(image_hash(whole), image_hash(split));
  float covered = 0;
  for (float a : whole.alpha) covered += a;
  EXPECT_GT(covered, 1.0f);  // the sphere and its shadow are in view
}

// The objects look as they would over a real ground of the catcher's albedo: lit by its
// bounce light from below and by no sky through it. A white sphere resting on the catcher
// against the same sphere on a large real square of that albedo (mean over the pixels the
// sphere covers; 2%, the noise of 64 samples over ~200 pixels is under 0.5%).
TEST(ShadowCatcher, ObjectsAreLitAsOverARealGroundOfItsAlbedo) {
  Scene scene = sphere_over_ground(Camera{{0, 0.6f, 4}, {0, 0.4f, 0}, {0, 1, 0}, 25.0f}, kRadius);
  scene.materials[0].base_color = Vec3(0.8f);
  const int w = 32, h = 32;
  const Framebuffer ar =
      testing::render_regions(scene, w, h, catcher_settings(64), {{0, 0, w, h}}, 1, 2);
  Scene real = scene;
  const uint32_t ground = add_material(real, Material{.name = "ground", .base_color = Vec3(0.5f)});
  add_quad(real, {-1000, 0, -1000}, {-1000, 0, 1000}, {1000, 0, 1000}, {1000, 0, -1000}, ground);
  RenderSettings plain = catcher_settings(64);
  plain.catcher_axis = -1;
  const Framebuffer ref = testing::render_regions(real, w, h, plain, {{0, 0, w, h}}, 1, 2);
  double ours = 0, theirs = 0;
  int covered = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (alpha_at(ar, x, y) == 1.0f) {
        ours += luminance(ar.at(x, y)), theirs += luminance(ref.at(x, y));
        ++covered;
      }
  ASSERT_GT(covered, 100);
  EXPECT_NEAR(ours / theirs, 1.0, 0.02);
}

TEST(CatcherPixel, ResolvesCoverageAndShadow) {
  CatcherPixel px;
  px.add(SampleKind::object, Vec3(2.0f), Vec3(0.0f));
  px.add(SampleKind::catcher, Vec3(0.25f), Vec3(1.0f));
  px.add(SampleKind::catcher, Vec3(0.25f), Vec3(1.0f));
  px.add(SampleKind::background, Vec3(7.0f), Vec3(7.0f));
  EXPECT_FLOAT_EQ(px.shadow_ratio(), 0.25f);
  Vec3 rgb;
  float alpha = 0;
  px.resolve(4, rgb, alpha);
  EXPECT_TRUE(same(rgb, Vec3(0.5f)));
  EXPECT_FLOAT_EQ(alpha, (1.0f + 2.0f * 0.75f) / 4.0f);
  // Light the objects add to the ground is not added: the ratio stays at most 1.
  CatcherPixel bright;
  bright.add(SampleKind::catcher, Vec3(3.0f), Vec3(1.0f));
  EXPECT_EQ(bright.shadow_ratio(), 1.0f);
  // No light without the objects: the real image is kept.
  CatcherPixel dark;
  dark.add(SampleKind::catcher, Vec3(0.0f), Vec3(0.0f));
  EXPECT_EQ(dark.shadow_ratio(), 1.0f);
}

}  // namespace shadow_catcher_test
}  // namespace multiray
