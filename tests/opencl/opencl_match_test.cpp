// The OpenCL image against the CPU's: the same estimator, so per-pixel means agree within
// their noise (z-test over independent seeds), and with the same seed the same random
// numbers, so most pixels agree to float rounding.
//
// The z-test. Each side renders B = 32 independent images (seeds 1000+b on the CPU,
// 2000+b on OpenCL, so the two sides share no random numbers) of S samples per pixel. Per
// pixel and channel, z = (mean_cl - mean_cpu) / sqrt(var_cl / B + var_cpu / B) with the
// sample variances of the B images. Under "same distribution" z follows Student's t with
// about 2(B - 1) = 62 degrees of freedom, so P(|z| > 4) ~ 1.7e-4 per channel: about 0.5 of
// the 3072 channels of a 32 x 32 image are expected beyond 4. The test fails when more
// than 1% of them (31) are, a false-alarm rate below 1e-30 if channels were independent
// and normal. Heavy-tailed pixels (caustics, the light's edge) push real counts above the
// t prediction; the bound leaves room for that yet catches a wrong material, light or
// camera, which shifts whole regions by many sigma. A second check catches small biases
// spread over the image: the mean of all z, which is 0 by symmetry and has a standard
// deviation of about 1/sqrt(3072) = 0.018, must stay within +-0.1 (5.5 sigma).
// All seeds are fixed, so the outcome is deterministic on a given OpenCL implementation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "opencl_ztest.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_match_test {

using testing::batches;
using testing::expect_matches_cpu;
using testing::render_whole;
using testing::summarize;
using testing::view_of;
using testing::ZSummary;

constexpr int kW = testing::kMatchW, kH = testing::kMatchH;

// The share of channels of `b` within 1e-3 (relative above 1) of `a`'s: how nearly two
// renders with the same seed agree.
double share_within_1e3(const Framebuffer& a, const Framebuffer& b) {
  size_t close = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      close += std::abs(a.pixels[i][c] - b.pixels[i][c]) <= 1e-3f * std::max(1.0f, a.pixels[i][c]);
  return double(close) / double(3 * a.pixels.size());
}

// The Cornell box: Lambert, a rough GGX conductor, one area light.
TEST(OpenClMatch, CornellBoxMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  expect_matches_cpu(make_cornell_box(), 8);
}

// Smooth shading from vertex normals: a coarse sphere (8 x 16 quads) under a small light
// and a dim sky, whose facets would show if either backend ignored the normals. The test
// has the power to see that: the CPU's own flat-shaded image fails it.
TEST(OpenClMatch, SmoothNormalsMatchCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene smooth = make_lit_sphere(0.8f, 8, 16, true), flat = make_lit_sphere(0.8f, 8, 16, false);
  smooth.environment = flat.environment = Vec3(0.1f);
  expect_matches_cpu(smooth, 8);
  SceneCache rs_smooth(smooth), rs_flat(flat);
  CpuDevice cpu_smooth(rs_smooth, {}, "cpu"), cpu_flat(rs_flat, {}, "cpu");
  const ZSummary z = summarize(
      testing::z_scores(batches(cpu_flat, flat, 8, 2000), batches(cpu_smooth, smooth, 8, 1000)));
  std::printf("flat vs smooth on the CPU: %.3f%% of channels beyond |z| = 4\n", 100 * z.beyond4);
  EXPECT_GT(z.beyond4, 0.05);
}

// The same box with the rest of the material model: a textured floor and walls (8-bit sRGB,
// bilinear, wrapped), a rough glass ball, a half-metallic red wall.
TEST(OpenClMatch, TexturesAndGlassMatchCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = make_cornell_box();
  scene.name = "cornell-box-textured-glass";
  for (const Vec3& p : scene.positions) scene.uvs.push_back({1.3f * p.x + 0.7f * p.y, 1.1f * p.z});
  unsigned char checker[4 * 4 * 3];
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c)
      checker[3 * i + c] = ((i + i / 4) % 2) ? 230 : uint8_t(40 + 60 * c);
  scene.textures.push_back(Texture::from_pixels(checker, 4, 4, 3));
  for (Material& m : scene.materials) {
    if (m.name == "white") m.base_color_texture = 0;
    if (m.name == "metal") m.transmission = 1.0f, m.roughness = 0.2f, m.ior = 1.5f;
    if (m.name == "red") m.metallic = 0.5f, m.roughness = 0.4f;
  }
  validate(scene);
  expect_matches_cpu(scene, 8);
}

// Same seed, same random numbers: the port of the RNG and of the order in which paths
// draw from it is exact, so nearly every pixel equals the CPU's to float rounding (a few
// paths diverge when an ulp of difference flips a Russian-roulette or lobe decision).
TEST(OpenClMatch, SameSeedGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, {}, "cpu");
  OpenClDevice cl(rs, {}, "opencl:0");
  const RenderSettings s{.spp = 4, .max_bounces = 6, .seed = 5};
  const Framebuffer a = render_whole(cpu, view_of(scene, kW, kH), s);
  const Framebuffer b = render_whole(cl, view_of(scene, kW, kH), s);
  const double fraction = share_within_1e3(a, b);
  std::printf("same seed: %.2f%% of channels within 1e-3\n", 100 * fraction);
  EXPECT_GE(fraction, 0.9);
}

// --clamp on both backends: the same shared clamp (render/shared/sampling.h) after the same
// paths, so the images agree as closely as without it, and neither has a pixel above the
// limit. The limit (1) is below the light (17, 12, 4) and the brightest indirect paths, so
// clamping changes many pixels: an OpenCL kernel ignoring the setting fails the bound.
TEST(OpenClMatch, SameSeedWithClampGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, {}, "cpu");
  OpenClDevice cl(rs, {}, "opencl:0");
  constexpr float kLimit = 1.0f;
  const RenderSettings off{.spp = 4, .max_bounces = 6, .seed = 5};
  RenderSettings on = off;
  on.sample_clamp = kLimit;
  const auto brightest = [](const Framebuffer& f) {
    float m = 0;
    for (const Vec3& p : f.pixels) m = std::max(m, max_component(p));
    return m;
  };
  ASSERT_GT(brightest(render_whole(cl, view_of(scene, kW, kH), off)), kLimit);
  const Framebuffer a = render_whole(cpu, view_of(scene, kW, kH), on);
  const Framebuffer b = render_whole(cl, view_of(scene, kW, kH), on);
  EXPECT_LE(brightest(a), kLimit * (1 + 1e-6f));
  EXPECT_LE(brightest(b), kLimit * (1 + 1e-6f));
  const double fraction = share_within_1e3(a, b);
  std::printf("same seed, --clamp %g: %.2f%% of channels within 1e-3\n", kLimit, 100 * fraction);
  EXPECT_GE(fraction, 0.9);
}

// Irregular sampling: a per-pixel sample map (0 to 6 samples) is honoured the same way,
// pixels without samples are black, and the sample count is reported exactly.
TEST(OpenClMatch, SampleMapGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, {}, "cpu");
  OpenClDevice cl(rs, {}, "opencl:0");
  std::vector<uint8_t> map(size_t(kW) * kH);
  uint64_t total = 0;
  for (size_t i = 0; i < map.size(); ++i) total += map[i] = uint8_t((i * 7 + i / kW) % 7);
  ViewSetup view = view_of(scene, kW, kH);
  view.spp_map = &map;
  const RenderSettings s{.spp = 4, .max_bounces = 6, .seed = 9};
  const Framebuffer a = render_whole(cpu, view, s);
  std::vector<Framebuffer> out{Framebuffer(kW, kH)};
  FrameJob job{{view}, s, &out};
  ListWorkSource whole({WorkItem{{0, 0, kW, kH}, 0}});
  const DeviceReport r = cl.render(job, whole, 0);
  ASSERT_FALSE(r.failed) << r.error;
  EXPECT_EQ(r.samples, total);
  const Framebuffer& b = out[0];
  for (size_t i = 0; i < a.pixels.size(); ++i)
    if (map[i] == 0) {
      EXPECT_EQ(max_component(b.pixels[i]), 0.0f);
    }
  EXPECT_GE(share_within_1e3(a, b), 0.9);
}

}  // namespace opencl_match_test
}  // namespace multiray
