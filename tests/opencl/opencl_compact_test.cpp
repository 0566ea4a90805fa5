// The compact scene on the OpenCL device (opencl:N:compact=1, issue 11): the kernel decodes
// the quantized mesh and traverses the quantized tree as the CPU's compact path does, so
// its image agrees with the CPU compact image (same seed, nearly channel for channel),
// meets the analytic answers, is bit-identical for any split, and the device holds fewer
// scene bytes; an emulated memory limit refuses what does not fit.
#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"
#include "device/scene_memory.h"
#include "opencl_ztest.h"
#include "render/compact_scene.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_compact_test {

using testing::render_on;
using testing::render_whole;
using testing::view_of;

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// A smooth sphere (corner normals, decoded from octahedral codes) on a ground quad without
// normals (the face normal of the decoded corners), lit by a lamp and the sky.
Scene ball_scene() {
  Scene s;
  s.name = "ball-compact";
  const uint32_t ball = add_material(
      s, Material{.name = "ball", .base_color = {0.9f, 0.6f, 0.3f}, .roughness = 0.4f});
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

TEST(OpenClCompact, FurnaceEveryPixelEqualsLeOverOneMinusAlbedo) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const float albedo = 0.5f;
  const Scene scene = make_furnace_sphere(albedo, 1.0f);
  SceneCache rs(scene);
  OpenClDevice device(rs, {.compact = true}, "opencl:0:compact=1");
  RenderSettings s{.spp = 256, .max_bounces = 40};
  s.rr_start = 1 << 20;
  const Framebuffer fb = render_whole(device, view_of(scene, 8, 8), s);
  for (const Vec3& p : fb.pixels)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], 2.0f, 0.02f);
}

// Same decoded triangles, same traversal arithmetic, same random numbers: the OpenCL
// compact image equals the CPU compact image nearly channel for channel, and matches it
// statistically over independent seeds.
TEST(OpenClCompact, AgreesWithTheCpuCompactImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  for (const Scene& scene : {make_cornell_box(), ball_scene()}) {
    EXPECT_GE(testing::same_seed_agreement(scene, true, true), 0.9) << scene.name;
    testing::expect_matches_cpu(scene, 4, true);
  }
}

// The test above can fail: the full-precision kernel's image of a scene whose compact
// geometry differs visibly is not the CPU compact image. The ball scene is made so by a
// field of 40,000 small separate quads far below it (160,000 distinct vertices over 8,000
// units): the cell-index table holds 2^16 geometry cells, so the field forces cells of tens
// of units, and the ball's vertices move by a few percent of its radius. (A single far
// quad no longer does: only occupied cells count.)
TEST(OpenClCompact, SameSeedAgreementSeesTheQuantization) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = ball_scene();
  const uint32_t far = add_material(scene, Material{.name = "far", .base_color = Vec3(0.5f)});
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      const float x = -4000.0f + 40.0f * float(i), z = -4000.0f + 40.0f * float(j);
      add_quad(scene, {x, -200, z}, {x, -200, z + 32}, {x + 32, -200, z + 32}, {x + 32, -200, z},
               far);
    }
  SceneCache rs(scene);
  CpuDevice cpu(rs, {.compact = true}, "cpu");
  OpenClDevice full(rs, {}, "opencl:0");
  OpenClDevice compact(rs, {.compact = true}, "opencl:0:compact=1");
  const ViewSetup view = view_of(scene, 32, 32);
  const RenderSettings s{.spp = 4, .max_bounces = 6, .seed = 5};
  const Framebuffer ref = render_whole(cpu, view, s);
  const auto agreement = [&](const Framebuffer& b) {
    size_t close = 0;
    for (size_t i = 0; i < ref.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c)
        close += std::abs(ref.pixels[i][c] - b.pixels[i][c]) <=
                 1e-3f * std::max(1.0f, ref.pixels[i][c]);
    return double(close) / double(3 * ref.pixels.size());
  };
  const double with_compact = agreement(render_whole(compact, view, s));
  const double with_full = agreement(render_whole(full, view, s));
  std::printf("coarse grid: compact kernel %.3f, full-precision kernel %.3f agree\n", with_compact,
              with_full);
  EXPECT_GE(with_compact, 0.9);
  EXPECT_LT(with_full, 0.75);  // 0.53 measured: sky and shadowed ground agree anyway
}

// The Cornell box with a 2 x 2 texture as base colour and emission and a cut-out
// material, its uvs from `uv_of` (vertex index -> uv).
template <class UvOf>
Scene textured_cornell(UvOf uv_of) {
  Scene scene = make_cornell_box();
  // Emission and base colour textures read uvs at hits, light samples and cut-out tests.
  Texture t = Texture::from_pixels(std::vector<unsigned char>{255, 40, 40, 255, 40, 255, 40, 0, 40,
                                                              40, 255, 255, 250, 250, 20, 0}
                                       .data(),
                                   2, 2, 4, TexelCoding::srgb);
  scene.textures.push_back(t);
  for (Material& m : scene.materials) {
    m.base_color_texture = 0;
    if (max_component(m.emission) > 0) m.emission_texture = 0;
  }
  scene.materials.back().alpha_mode = AlphaMode::mask;
  scene.uvs.resize(scene.positions.size());
  for (size_t i = 0; i < scene.uvs.size(); ++i) scene.uvs[i] = uv_of(i);
  return scene;
}

TEST(OpenClCompact, CutoutsAndTexturesAgreeWithTheCpuCompactImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = textured_cornell([](size_t i) {
    return Vec2{float(i % 7) / 6.0f, float(i % 5) / 4.0f};
  });
  scene.name = "cornell-textured-compact";
  EXPECT_GE(testing::same_seed_agreement(scene, true, true), 0.9);
}

// Tiling uvs: the triangles' shifts differ, so the kernel decodes them from their packed
// entries (bits for u and for v, render/shared/compact.h) as the CPU does.
TEST(OpenClCompact, TilingUvsAgreeWithTheCpuCompactImage) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = textured_cornell([](size_t i) {
    return Vec2{float(i % 7) / 6.0f + float(i / 4 % 11) - 3.0f,
                float(i % 5) / 4.0f + float(i / 4 % 3) + 7.0f};
  });
  scene.name = "cornell-tiled-compact";
  const UvShifts shifts = build_compact_mesh(scene).uv_shifts;
  ASSERT_GT(shifts.bits[0], 0u);
  ASSERT_GT(shifts.bits[1], 0u);
  // 100% of channels measured; a kernel that reads v's shift from the wrong bits decodes
  // some corners a period off and agrees in 97%. (A shift off by a whole period alone
  // would not show: the texture repeats.)
  EXPECT_GE(testing::same_seed_agreement(scene, true, true), 0.995);
}

// Any split, any launch size, one device or two: bit for bit.
TEST(OpenClCompact, ImageIsBitIdenticalForAnySplit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 37, h = 23;
  const ViewSetup view = view_of(scene, w, h, 3);
  const RenderSettings s{.spp = 2, .max_bounces = 5, .seed = 7};
  OpenClDevice a(rs, {.compact = true}, "opencl:0:compact=1");
  const Framebuffer whole = render_whole(a, view, s);
  std::vector<Rect> tiles;
  for (int y = 0; y < h; y += 5)
    for (int x = 0; x < w; x += 7) tiles.push_back({x, y, std::min(w, x + 7), std::min(h, y + 5)});
  EXPECT_TRUE(same_bits(render_on({&a}, view, s, tiles), whole)) << "tiles";
  OpenClDevice b(rs, {.tile = 4, .work_group = 1, .compact = true},
                 "opencl:0:tile=4:wg=1:compact=1");
  EXPECT_TRUE(same_bits(render_whole(b, view, s), whole)) << "tile=4 wg=1";
  EXPECT_TRUE(same_bits(render_on({&a, &b}, view, s, tiles), whole)) << "two devices";
}

TEST(OpenClCompact, HoldsFewerSceneBytesAndSaysWhichRepresentation) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = ball_scene();
  SceneCache rs(scene);
  OpenClDevice full(rs, {}, "opencl:0");
  OpenClDevice compact(rs, {.compact = true}, "opencl:0:compact=1");
  EXPECT_EQ(full.info().representation, "opencl-flat-bvh");
  EXPECT_EQ(compact.info().representation, "opencl-compact");
  std::printf("scene buffers: flat %llu bytes, compact %llu bytes\n",
              (unsigned long long)full.info().scene_bytes,
              (unsigned long long)compact.info().scene_bytes);
  EXPECT_GT(compact.info().scene_bytes, 0u);
  EXPECT_LT(2 * compact.info().scene_bytes, full.info().scene_bytes);
}

// A limit between the compact and the full-precision estimates: full precision is refused
// before anything is built, compact=1 fits; a limit under both refuses both.
TEST(OpenClCompact, MemoryLimitRefusesWhatDoesNotFit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  Scene scene = ball_scene();
  add_sphere(scene, {2, 0, 0}, 0.5f, 100, 200, false, 0);
  SceneCache rs(scene);
  const uint64_t full = estimate_scene_bytes(scene, false);
  const uint64_t compact = estimate_scene_bytes(scene, true);
  ASSERT_LT(compact, full);
  const uint64_t limit = (compact + full) / 2;
  EXPECT_THROW(OpenClDevice(rs, {.memory_limit = limit}, "opencl:0:mem=test"), InputError);
  OpenClDevice fits(rs, {.compact = true, .memory_limit = limit}, "opencl:0:compact=1:mem=test");
  EXPECT_EQ(fits.info().memory_limit, limit);
  EXPECT_THROW(OpenClDevice(rs, {.compact = true, .memory_limit = compact - 1},
                            "opencl:0:compact=1:mem=test"),
               InputError);
}

}  // namespace opencl_compact_test
}  // namespace multiray
