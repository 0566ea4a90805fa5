// The OpenCL image against the CPU's for the features of the environment light and of
// per-texel materials, each by the z-test of opencl_ztest.h; each test also shows its
// power: the CPU image of the scene without the feature fails the same test. A same-seed
// test with every feature at once checks that the kernel draws the CPU's random numbers
// in the CPU's order.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "opencl_ztest.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_feature_match_test {

using testing::expect_matches_cpu;
using testing::expect_test_sees_feature;
using testing::same_seed_agreement;

// A glossy half-metal ball on a diffuse ground under a small lamp and a constant sky; the
// camera looks down at it, so the sky lights the image mostly through next-event
// estimation and BSDF samples weighted against it.
Scene sky_scene(const std::string& name) {
  Scene s;
  s.name = name;
  const uint32_t ball = add_material(
      s,
      Material{
          .name = "ball", .base_color = {0.9f, 0.6f, 0.3f}, .metallic = 0.5f, .roughness = 0.35f});
  const uint32_t ground = add_material(s, Material{.name = "ground", .base_color = Vec3(0.7f)});
  const uint32_t lamp = add_material(
      s, Material{.name = "lamp", .base_color = Vec3(0.0f), .emission = {6.0f, 5.0f, 4.0f}});
  add_sphere(s, {0, 0, 0}, 1.0f, 12, 24, false, ball);
  add_quad(s, {-4, -1, -4}, {-4, -1, 4}, {4, -1, 4}, {4, -1, -4}, ground);
  add_quad(s, {-1.5f, 3, -0.5f}, {-0.5f, 3, -0.5f}, {-0.5f, 3, 0.5f}, {-1.5f, 3, 0.5f}, lamp);
  s.environment = Vec3(0.6f, 0.7f, 0.8f);
  s.cameras.push_back(Camera{{0, 2.2f, 3.6f}, {0, -0.4f, 0}, {0, 1, 0}, 40.0f});
  return s;
}

// A 32 x 16 map: a blue-to-brown gradient with a bright yellow patch around (u, v) =
// (0.7, 0.3), to the +x side of the camera's view (mirrored to -x when `mirrored`).
std::shared_ptr<EnvironmentMap> test_map(bool mirrored) {
  auto map = std::make_shared<EnvironmentMap>();
  map->name = mirrored ? "test-map-mirrored" : "test-map";
  map->width = 32, map->height = 16;
  for (int y = 0; y < map->height; ++y)
    for (int x = 0; x < map->width; ++x) {
      const int mx = mirrored ? map->width - 1 - x : x;
      const float v = (float(y) + 0.5f) / float(map->height);
      Vec3 c = Vec3(0.3f, 0.5f, 1.0f) * (1.0f - v) + Vec3(0.3f, 0.2f, 0.1f) * v;
      if (std::abs(mx - 22) <= 1 && std::abs(y - 4) <= 1) c = Vec3(40.0f, 30.0f, 10.0f);
      map->radiance.push_back(c);
    }
  return map;
}

// Sky NEE (cosine-weighted around the normal) with MIS, mixed with the lamp.
TEST(OpenClFeatureMatch, ConstantSkyMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene with = sky_scene("sky-constant");
  expect_matches_cpu(with, 8);
  Scene without = with;
  without.environment = Vec3(0.0f);
  expect_test_sees_feature(with, without, 8);
}

// The map sampled from the host's tables; the power check mirrors the map (the same
// light, from the other side), so the test sees its orientation, not only its presence.
TEST(OpenClFeatureMatch, EnvironmentMapMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene with = sky_scene("sky-map");
  with.environment = Vec3(0.05f);
  with.environment_map = test_map(false);
  with.environment_map_scale = 1.5f;
  expect_matches_cpu(with, 8);
  Scene without = with;
  without.environment_map = test_map(true);
  expect_test_sees_feature(with, without, 8);
}

// A sun of irradiance ~3 (radiance x its cone's solid angle) beside a dim sky.
TEST(OpenClFeatureMatch, SunMatchesCpuStatistically) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene with = sky_scene("sky-sun");
  with.environment = Vec3(0.2f);
  with.sun.direction = normalize(Vec3(1.0f, 2.0f, 0.5f));
  const float cone = 2.0f * kPi * (1.0f - std::cos(with.sun.half_angle_rad));
  with.sun.radiance = Vec3(3.0f, 2.8f, 2.4f) * (1.0f / cone);
  expect_matches_cpu(with, 8);
  Scene without = with;
  without.sun.radiance = Vec3(0.0f);
  expect_test_sees_feature(with, without, 8);
}

// Sky, map, sun and lamp at once, sampled with the CPU's random numbers.
TEST(OpenClFeatureMatch, SameSeedUnderSkyMapAndSunGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = sky_scene("sky-map-sun");
  scene.environment_map = test_map(false);
  scene.sun.direction = normalize(Vec3(1.0f, 2.0f, 0.5f));
  scene.sun.radiance = Vec3(2e4f);
  EXPECT_GE(same_seed_agreement(scene), 0.9);
}

// The constant sky is sampled cosine-weighted in a frame around the geometric normal, whose
// orientation for an axis-aligned wall hangs on the sign of a zero component: the kernel
// computes the normal as Embree does (render/flat_bvh.h), so the closed box's walls draw the
// same directions as on the CPU.
TEST(OpenClFeatureMatch, SameSeedUnderConstantSkyInTheBoxGivesNearlyTheCpuImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = make_cornell_box();
  scene.name = "cornell-box-sky";
  scene.environment = Vec3(0.3f);
  EXPECT_GE(same_seed_agreement(scene), 0.9);
  // RenderSettings::sample_environment off: both leave the sky to BSDF sampling.
  EXPECT_GE(same_seed_agreement(scene, false), 0.9);
}

}  // namespace opencl_feature_match_test
}  // namespace multiray
