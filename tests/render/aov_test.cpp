// The path tracer's feature buffers (AOVs, render/shared/aov.h) on the CPU: the values
// on analytic scenes, the variance's definition checked sample by sample, the emission
// where a light is seen, the beauty
// untouched by asking for them, and the buffers as independent of the split as the image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/feature_buffers.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace aov_test {

RenderSettings with_features(int spp) {
  RenderSettings s;
  s.spp = spp;
  s.max_bounces = 8;
  s.feature_buffers = true;
  return s;
}

Framebuffer render(const Scene& scene, int w, int h, const RenderSettings& s,
                   const std::vector<Rect>& regions = {}, int devices = 1) {
  return testing::render_regions(
      scene, w, h, s, regions.empty() ? std::vector<Rect>{{0, 0, w, h}} : regions, devices);
}

// A diffuse plane of albedo 0.5 facing +y, seen straight down from height 1: every pixel
// has albedo 0.5, normal +y, and depth 1 along the camera's axis, whatever the ray's angle.
TEST(Aov, PlaneSeenFromAbove) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  const Framebuffer fb = render(scene, 24, 16, with_features(4));
  const FeatureBuffers& f = fb.features;
  ASSERT_EQ(f.width, 24);
  ASSERT_EQ(f.depth.size(), size_t(24 * 16));
  for (size_t i = 0; i < f.depth.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f.albedo[3 * i + size_t(c)], 0.5f) << i;
    EXPECT_NEAR(f.normal[3 * i], 0.0f, 1e-6f);
    EXPECT_NEAR(f.normal[3 * i + 1], 1.0f, 1e-6f);
    EXPECT_NEAR(f.normal[3 * i + 2], 0.0f, 1e-6f);
    EXPECT_NEAR(f.depth[i], 1.0f, 1e-4f) << i;
    EXPECT_GE(f.variance[i], 0.0f);
  }
}

// A path ends at its last bounce after recording: with --bounces 0 (emission only) the
// plane's features are still there, and the beauty is black.
TEST(Aov, RecordedAtTheLastBounce) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  RenderSettings s = with_features(2);
  s.max_bounces = 0;
  const Framebuffer fb = render(scene, 8, 8, s);
  for (size_t i = 0; i < fb.features.depth.size(); ++i) {
    EXPECT_EQ(fb.features.albedo[3 * i + 1], 0.5f) << i;
    EXPECT_NEAR(fb.features.depth[i], 1.0f, 1e-4f) << i;
    EXPECT_EQ(fb.pixels[i].y, 0.0f) << i;
  }
}

// Looking at the horizon: the rows above it see only sky (albedo and normal 0, depth
// +inf, and the sky's constant radiance has no variance); the rows below see the plane at
// the planar depth 1 / tan(angle below the axis).
TEST(Aov, MissesAndPlanarDepth) {
  Scene scene = make_lit_plane(0.5f, 1.0f);
  scene.cameras[0] = Camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 60.0f};
  const int w = 16, h = 16;
  const Framebuffer fb = render(scene, w, h, with_features(4));
  const FeatureBuffers& f = fb.features;
  for (int x = 0; x < w; ++x) {
    const size_t top = size_t(x), bottom = size_t((h - 1) * w + x);
    EXPECT_TRUE(std::isinf(f.depth[top]) && f.depth[top] > 0);
    EXPECT_EQ(f.albedo[3 * top], 0.0f);
    EXPECT_EQ(f.normal[3 * top + 1], 0.0f);
    EXPECT_EQ(f.variance[top], 0.0f);
    // The sky seen directly is all the top row's light: its emission is the beauty. The
    // plane is lit, not emitting: the bottom row's emission is 0 under a bright beauty.
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(f.emission[3 * top + size_t(c)], fb.pixels[top][c]) << x;
      EXPECT_EQ(f.emission[3 * bottom + size_t(c)], 0.0f) << x;
    }
    EXPECT_GT(fb.pixels[bottom].y, 0.05f);
    EXPECT_EQ(f.albedo[3 * bottom + 1], 0.5f);
    EXPECT_NEAR(f.normal[3 * bottom + 1], 1.0f, 1e-6f);
    // The bottom row's rays leave about tan(30 deg) * (1 - 1/16) below the axis.
    const float slope = std::tan(30.0f * kPi / 180.0f) * (1.0f - 1.0f / float(h));
    EXPECT_NEAR(f.depth[bottom], 1.0f / slope, 0.1f);
  }
}

// A pixel that sees only a light: its emission is the beauty, bit for bit, also when the
// sample clamp scales every sample down (the emission is scaled with its sample). The
// plane itself emits, is black (reflects nothing) and fills the view.
TEST(Aov, EmissionOfALightSeenDirectlyIsTheBeauty) {
  Scene scene = make_lit_plane(0.0f, 1.0f);
  scene.materials[0].emission = Vec3(4.0f, 2.0f, 1.0f);
  for (const float clamp : {0.0f, 3.0f}) {
    RenderSettings s = with_features(4);
    s.sample_clamp = clamp;
    const Framebuffer fb = render(scene, 12, 8, s);
    for (size_t i = 0; i < fb.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(fb.features.emission[3 * i + size_t(c)], fb.pixels[i][c]) << i << " " << clamp;
        EXPECT_GT(fb.pixels[i][c], 0.0f);
      }
    if (clamp > 0.0f) {
      EXPECT_FLOAT_EQ(fb.pixels[0].x, clamp);
    }
  }
}

// A light's radiance reflected off a diffuse surface is not emission: in the Cornell box
// only the pixels that see the light have some (at most its radiance, never more than
// the beauty); the rest of the box, lit by it, has none.
TEST(Aov, EmissionOnlyWhereALightIsSeen) {
  const Scene scene = make_cornell_box();
  const Framebuffer fb = render(scene, 32, 32, with_features(4));
  int lit = 0, emitting = 0;
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const float e = fb.features.emission[3 * i];
    EXPECT_GE(e, 0.0f);
    EXPECT_LE(e, fb.pixels[i].x) << i;  // never more than the beauty
    if (e > 0.0f) {
      ++emitting;
      EXPECT_LE(e, 17.0f) << i;  // the light's radiance, red
    } else if (fb.pixels[i].x > 0.0f) {
      ++lit;
    }
  }
  EXPECT_GT(emitting, 0);
  // The light covers about 1% of the view (12 of these 1024 pixels); light reflected
  // first and then reaching the light would add emission to some 50.
  EXPECT_LT(emitting, int(fb.pixels.size()) / 40);
  EXPECT_GT(lit, int(fb.pixels.size()) / 2);
}

// The variance is the variance of the pixel's mean luminance less its emission, from its
// own samples: rendered sample by sample (first_sample = k, one sample each, the sample's
// emission in its feature buffers) and computed here in double, it agrees with the buffer
// of the render of all of them; where a pixel sees the light's edge, the beauty's own
// variance would not.
TEST(Aov, VarianceOfTheMeanLuminance) {
  const Scene scene = make_cornell_box();
  const int w = 12, h = 8, n = 8;
  SceneCache cache(scene);
  PathTracer tracer(cache.mesh(false));
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = w, view.height = h;
  Framebuffer all(w, h);
  all.features.resize(w, h);
  tracer.render_rect(view, with_features(n), {0, 0, w, h}, all);
  std::vector<std::vector<double>> y(size_t(w * h)), beauty(size_t(w * h));
  for (int k = 0; k < n; ++k) {
    ViewSetup one = view;
    one.first_sample = uint32_t(k);
    Framebuffer fb(w, h);
    fb.features.resize(w, h);
    tracer.render_rect(one, with_features(1), {0, 0, w, h}, fb);
    for (size_t i = 0; i < fb.pixels.size(); ++i) {
      const Vec3 c = fb.pixels[i];
      const float* e = &fb.features.emission[3 * i];
      y[i].push_back(0.2126 * (c.x - e[0]) + 0.7152 * (c.y - e[1]) + 0.0722 * (c.z - e[2]));
      beauty[i].push_back(0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
    }
  }
  const auto variance_of_mean = [&](const std::vector<double>& v) {
    double mean = 0, m2 = 0;
    for (double x : v) mean += x / n;
    for (double x : v) m2 += (x - mean) * (x - mean);
    return m2 / (n - 1) / n;
  };
  int varied = 0, edges = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    const double expected = variance_of_mean(y[i]);
    EXPECT_NEAR(all.features.variance[i], expected, 1e-4 * expected + 1e-7) << "pixel " << i;
    varied += expected > 1e-6;
    edges += variance_of_mean(beauty[i]) > 2 * expected + 1e-3;  // the light's spread
  }
  EXPECT_GT(varied, w * h / 2);  // the check is not all zeros
  EXPECT_GT(edges, 0);           // and some pixel tells the two variances apart
}

// Asking for the buffers changes no bit of the beauty.
TEST(Aov, BeautyUnchanged) {
  const Scene scene = make_cornell_box();
  RenderSettings plain{.spp = 3, .max_bounces = 8};
  const Framebuffer a = render(scene, 31, 17, plain);
  const Framebuffer b = render(scene, 31, 17, with_features(3));
  EXPECT_TRUE(a.features.empty());
  EXPECT_EQ(image_hash(a), image_hash(b));
}

// The strongest invariant, for the buffers too: any split, any number of devices.
TEST(Aov, SplitIndependent) {
  const Scene scene = make_cornell_box();
  const int w = 61, h = 37;
  const RenderSettings s = with_features(2);
  const Framebuffer whole = render(scene, w, h, s);
  const std::vector<Rect> regions{{0, 0, 13, 37},  {13, 0, 61, 5},  {13, 5, 40, 6}, {40, 5, 61, 6},
                                  {13, 6, 14, 37}, {14, 6, 50, 37}, {50, 6, 61, 37}};
  const Framebuffer split = render(scene, w, h, s, regions, 3);
  EXPECT_EQ(feature_hash(whole.features), feature_hash(split.features));
  EXPECT_EQ(image_hash(whole), image_hash(split));
  // The hash can tell: another frame's samples give another variance.
  const Framebuffer other = testing::render_regions(scene, w, h, s, {{0, 0, w, h}}, 1, 1, 1);
  EXPECT_NE(feature_hash(whole.features), feature_hash(other.features));
}

// Through glass: the first non-specular vertex is behind it. A smooth glass slab
// (dielectric) at height 0.5 over the lit plane: pixels whose samples all went through
// have the plane's albedo and a depth past the glass (paths reflected to the sky keep the
// glass, the first surface they met: albedo 1, depth 0.5).
TEST(Aov, SeesThroughGlass) {
  Scene scene = make_lit_plane(0.5f, 1.0f);
  Material glass{.name = "glass", .base_color = Vec3(1.0f)};
  glass.transmission = 1.0f;
  glass.roughness = 0.0f;
  const uint32_t m = add_material(scene, glass);
  add_quad(scene, {-5, 0.5f, -5}, {-5, 0.5f, 5}, {5, 0.5f, 5}, {5, 0.5f, -5}, m);
  const Framebuffer fb = render(scene, 8, 8, with_features(2));
  int through = 0;
  for (size_t i = 0; i < fb.features.depth.size(); ++i) {
    EXPECT_GE(fb.features.albedo[3 * i], 0.5f);
    if (fb.features.albedo[3 * i] != 0.5f) continue;
    ++through;
    EXPECT_GT(fb.features.depth[i], 0.75f) << i;
  }
  EXPECT_GT(through, 32);
}

}  // namespace aov_test
}  // namespace multiray
