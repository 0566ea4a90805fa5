// --clamp (RenderSettings::sample_clamp): each camera sample's radiance is scaled so that its
// largest component is at most the limit, before the pixel's average. The shared function
// against hand-worked values, and the path tracer on a scene made of fireflies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "render/render_helpers.h"
#include "render/shared/sampling.h"
#include "scene/builders.h"

namespace multiray {
namespace clamp_test {

constexpr int kW = 64, kH = 48;

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

TEST(ClampSample, ScalesTheLargestComponentToTheLimitKeepingTheHue) {
  const Vec3 c = clamp_sample(Vec3(8.0f, 4.0f, 2.0f), 4.0f);
  EXPECT_FLOAT_EQ(c.x, 4.0f);
  EXPECT_FLOAT_EQ(c.y, 2.0f);
  EXPECT_FLOAT_EQ(c.z, 1.0f);
  EXPECT_FLOAT_EQ(clamp_sample(Vec3(0.5f, 30.0f, 3.0f), 3.0f).y, 3.0f);
}

TEST(ClampSample, OffOrWithinTheLimitLeavesTheSampleUnchanged) {
  const Vec3 a(1e6f, 2.0f, 0.0f), b(3.9f, 4.0f, 0.1f);
  EXPECT_TRUE(same(clamp_sample(a, 0.0f), a));
  EXPECT_TRUE(same(clamp_sample(b, 4.0f), b));
  EXPECT_TRUE(same(clamp_sample(Vec3(0.0f), 1.0f), Vec3(0.0f)));
}

// Fireflies by construction: a white floor, a mirror wall behind it and a small bright
// light (20 cm square, radiance 400) above, with a camera looking straight down at the
// floor, which sees neither the light nor the mirror. The floor's direct light is smooth
// (next-event estimation), but a diffuse bounce that happens to hit the light's image in
// the mirror (about 1 sample in 1000) brings back about 0.8 x 400: a firefly.
Scene firefly_scene() {
  Scene s;
  s.name = "fireflies";
  const uint32_t white = add_material(s, Material{.name = "white", .base_color = Vec3(0.8f)});
  const uint32_t mirror = add_material(
      s, Material{.name = "mirror", .base_color = Vec3(0.95f), .metallic = 1.0f, .roughness = 0});
  const uint32_t light =
      add_material(s, Material{.name = "light", .base_color = Vec3(0), .emission = Vec3(400)});
  add_quad(s, {-2, 0, -0.5f}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -0.5f}, white);           // floor, up
  add_quad(s, {-2, 0, -0.5f}, {2, 0, -0.5f}, {2, 2, -0.5f}, {-2, 2, -0.5f}, mirror);  // +z
  add_quad(s, {-0.1f, 1.5f, -0.1f}, {0.1f, 1.5f, -0.1f}, {0.1f, 1.5f, 0.1f}, {-0.1f, 1.5f, 0.1f},
           light);  // facing down
  s.cameras = {Camera{{0, 1, 0.5f}, {0, 0, 0.5f}, {0, 0, -1}, 60.0f}};
  validate(s);
  return s;
}

Framebuffer render(const Scene& scene, int spp, float clamp, int bounces = 8) {
  const RenderSettings s{.spp = spp, .max_bounces = bounces, .seed = 3, .sample_clamp = clamp};
  return testing::render_regions(scene, kW, kH, s, {{0, 0, kW, kH}});
}

float max_pixel(const Framebuffer& fb) {
  float m = 0;
  for (const Vec3& p : fb.pixels) m = std::max(m, max_component(p));
  return m;
}

TEST(PathClamp, TheFireflySceneNeverShowsTheLightDirectly) {
  EXPECT_EQ(max_pixel(render(firefly_scene(), 1, 0.0f, 0)), 0.0f);  // emission at depth 0 only
}

// One sample per pixel: a pixel is its sample, so a sample within the limit must come out
// bit for bit, and one above it scaled to the limit with its ratios kept.
TEST(PathClamp, OneSampleAPixelIsTheClampOfTheUnclampedSample) {
  constexpr float kLimit = 2.0f;
  const Scene scene = firefly_scene();
  const Framebuffer off = render(scene, 1, 0.0f), on = render(scene, 1, kLimit);
  int clamped = 0;
  for (size_t i = 0; i < off.pixels.size(); ++i) {
    const Vec3 a = off.pixels[i], b = on.pixels[i];
    if (max_component(a) <= kLimit) {
      EXPECT_TRUE(same(a, b)) << "pixel " << i;
      continue;
    }
    ++clamped;
    EXPECT_NEAR(max_component(b), kLimit, 1e-5f * kLimit) << "pixel " << i;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c] * max_component(a), a[c] * kLimit, 1e-4f * a[c]);
  }
  EXPECT_GT(clamped, 0) << "no sample above the limit: the scene has no fireflies";
}

// The case: at 16 samples the fireflies still stand out far above the limit; with
// --clamp no pixel exceeds it (a mean of samples that each stay within it).
TEST(PathClamp, BoundsEveryPixelOfAnImageWithFireflies) {
  constexpr float kLimit = 4.0f;
  const Scene scene = firefly_scene();
  const Framebuffer off = render(scene, 16, 0.0f);
  int fireflies = 0;
  for (const Vec3& p : off.pixels) fireflies += max_component(p) > 2 * kLimit;
  std::printf("16 spp without --clamp: %d pixels above %g, the brightest %.1f\n", fireflies,
              2 * kLimit, max_pixel(off));
  EXPECT_GT(fireflies, 0);
  EXPECT_LE(max_pixel(render(scene, 16, kLimit)), kLimit * (1 + 1e-6f));
}

TEST(PathClamp, ZeroIsOffBitForBit) {
  const Scene scene = firefly_scene();
  EXPECT_EQ(image_hash(render(scene, 4, 0.0f)), image_hash(render(scene, 4, 1e30f)));
}

}  // namespace clamp_test
}  // namespace multiray
