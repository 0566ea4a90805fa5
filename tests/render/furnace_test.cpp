// Analytic scenes with known answers.
#include <gtest/gtest.h>

#include <cstring>

#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace furnace_test {

// White furnace: inside a closed sphere with albedo rho and emission Le, the radiance is
// Le / (1 - rho) everywhere. Russian roulette is off and bounces are many, so the
// truncation error (rho^41) is far below the 1% tolerance.
TEST(Furnace, EveryPixelEqualsLeOverOneMinusAlbedo) {
  for (float albedo : {0.5f, 0.8f}) {
    const float le = 1.0f;
    const Scene scene = make_furnace_sphere(albedo, le);
    RenderSettings s;
    s.spp = 256;
    s.max_bounces = albedo > 0.6f ? 80 : 40;
    s.rr_start = 1 << 20;
    const int w = 16, h = 16;
    const Framebuffer fb = testing::render_regions(scene, w, h, s, {{0, 0, w, h}}, 1, 2);
    const float expected = le / (1.0f - albedo);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(fb.at(x, y)[c], expected, 0.01f * expected)
              << "albedo " << albedo << " pixel " << x << "," << y;
  }
}

// Direct illumination in the furnace: the emission seen (Le) plus one bounce of it
// (albedo x Le), whatever --bounces says; the path tracer with one bounce is the same.
TEST(Furnace, DirectLightingIsLeTimesOnePlusAlbedo) {
  const float albedo = 0.6f, le = 1.0f;
  const Scene scene = make_furnace_sphere(albedo, le);
  RenderSettings s;
  s.kernel = "direct";
  s.spp = 256;
  s.max_bounces = 40;
  const Framebuffer fb = testing::render_regions(scene, 8, 8, s, {{0, 0, 8, 8}}, 1, 2);
  for (const Vec3& p : fb.pixels)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], le * (1.0f + albedo), 0.01f * le);
  RenderSettings one = s;
  one.kernel = "path";
  one.max_bounces = 1;
  const Framebuffer path = testing::render_regions(scene, 8, 8, one, {{0, 0, 8, 8}}, 1, 2);
  EXPECT_EQ(std::memcmp(path.pixels.data(), fb.pixels.data(), fb.pixels.size() * sizeof(Vec3)), 0);
}

// A diffuse plane under a constant sky sees the whole sky hemisphere, so its radiance is
// albedo * sky exactly; with cosine sampling every path returns that value (no noise).
TEST(LitPlane, RadianceIsAlbedoTimesSky) {
  const Scene scene = make_lit_plane(0.5f, 2.0f);
  RenderSettings s;
  s.spp = 4;
  s.max_bounces = 4;
  const Framebuffer fb = testing::render_regions(scene, 24, 16, s, {{0, 0, 24, 16}});
  for (const Vec3& p : fb.pixels)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], 1.0f, 1e-4f);
}

// The same plane with zero bounces shows only direct emission: black.
TEST(LitPlane, ZeroBouncesSeeNoLight) {
  const Scene scene = make_lit_plane(0.5f, 2.0f);
  RenderSettings s;
  s.spp = 1;
  s.max_bounces = 0;
  const Framebuffer fb = testing::render_regions(scene, 8, 8, s, {{0, 0, 8, 8}});
  for (const Vec3& p : fb.pixels) ASSERT_EQ(max_component(p), 0.0f);
}

// Cornell box: the light is visible and brighter than the walls; the image has no NaN.
TEST(CornellBox, RendersFiniteImageWithVisibleLight) {
  const Scene scene = make_cornell_box();
  RenderSettings s;
  s.spp = 4;
  const Framebuffer fb = testing::render_regions(scene, 64, 64, s, {{0, 0, 64, 64}}, 1, 2);
  float top = 0, mean = 0;
  for (const Vec3& p : fb.pixels) {
    ASSERT_TRUE(is_finite(p));
    mean += luminance(p) / float(fb.pixels.size());
  }
  for (int y = 0; y < 20; ++y)  // the light is in the upper part of the image
    for (int x = 24; x < 40; ++x) top = std::max(top, luminance(fb.at(x, y)));
  EXPECT_GT(mean, 0.05f);
  EXPECT_GT(top, 5.0f);  // emission ~12 luminance
}

}  // namespace furnace_test
}  // namespace multiray
