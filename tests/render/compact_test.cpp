// The compact scene (Seo, Park & Ihm 2022, §3): quantization error bounds, round trips,
// degenerate scenes, a traversal that finds exactly the hits of the decoded triangles,
// images within the PSNR bound of full precision, split independence and the `mem=` limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "core/error.h"
#include "core/image_metrics.h"
#include "device/scene_memory.h"
#include "render/compact_accel.h"
#include "render/compact_scene.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace compact_test {

float angle_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.0f, 1.0f)) * 57.29578f;
}

TEST(CompactQuantize, PositionErrorIsAtMostACell_1024thPerAxis) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  const Bounds3 boxes[] = {{{-1, -1, -1}, {1, 1, 1}},
                           {{0, 0, 0}, {1000, 3, 0.01f}},
                           {{-1e4f, 5, 5}, {1e4f, 5.5f, 9}},
                           {{3, 3, 3}, {3, 3, 4}}};  // flat in x and y
  for (const Bounds3& b : boxes) {
    const PositionGrid g = PositionGrid::fit(b);
    ASSERT_LE(uint64_t(g.n[0]) * g.n[1] * g.n[2], kMaxGridCells);
    for (int a = 0; a < 3; ++a)  // the grid covers the box
      EXPECT_GE(double((&g.origin.x)[a]) + double(g.n[a]) * g.cell, double((&b.hi.x)[a]));
    const float bound = g.cell / 1024.0f;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 p = b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent();
      const Vec3 d = decode_position(g, encode_position(g, p));
      EXPECT_LE(std::fabs(d.x - p.x), bound + 1e-6f * std::fabs(p.x));
      EXPECT_LE(std::fabs(d.y - p.y), bound + 1e-6f * std::fabs(p.y));
      EXPECT_LE(std::fabs(d.z - p.z), bound + 1e-6f * std::fabs(p.z));
    }
  }
}

// Bisection finds (nearly) the smallest cell: 1% smaller needs more than 65,536 cells.
TEST(CompactQuantize, GridCellIsTheSmallestThatFits) {
  const Bounds3 b{{0, 0, 0}, {10, 4, 2.5f}};
  const PositionGrid g = PositionGrid::fit(b);
  const double c = g.cell * 0.99;
  const double cells = std::ceil(10 / c) * std::ceil(4 / c) * std::ceil(2.5 / c);
  EXPECT_GT(cells, double(kMaxGridCells));
}

// The multiply-high division of cell indices equals the integer division for every
// 16-bit index and every divisor a grid can have at its extremes and in between.
TEST(CompactQuantize, CellIndexDivisionIsExact) {
  std::vector<uint32_t> divisors = {1, 2, 3, 7, 255, 256, 257, 4095, 32767, 32768, 65535, 65536};
  std::mt19937 rng(11);
  for (int i = 0; i < 100; ++i) divisors.push_back(1 + rng() % 65536);
  for (uint32_t d : divisors) {
    const uint32_t magic = division_magic(d);
    for (uint32_t x = 0; x < 65536; ++x) ASSERT_EQ(divide_u16(x, magic), x / d) << x << " / " << d;
  }
}

TEST(CompactQuantize, PositionCodesRoundTrip) {
  const PositionGrid g = PositionGrid::fit(Bounds3{{-2, 0, 1}, {5, 1, 3}});
  std::mt19937 rng(3);
  for (int i = 0; i < 20000; ++i) {
    const uint32_t cell = rng() % (g.n[0] * g.n[1] * g.n[2]);
    const uint32_t off = rng() & 0x3fffffffu;
    const QuantizedPosition q{uint16_t(cell), uint16_t(off & 0xffff), uint16_t(off >> 16)};
    const Vec3 p = decode_position(g, q);
    const Vec3 again = decode_position(g, encode_position(g, p));
    EXPECT_LE(length(again - p), 1e-5f);
  }
}

TEST(CompactQuantize, NormalErrorIsUnderTheTablesBound) {
  std::mt19937 rng(11);
  std::normal_distribution<float> n(0, 1);
  float worst = 0;
  for (int i = 0; i < 300000; ++i) {
    const Vec3 v(n(rng), n(rng), n(rng));
    if (length(v) < 1e-3f) continue;
    worst = std::max(worst, angle_deg(v, decode_normal(encode_normal(v))));
  }
  for (const Vec3 v : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(1, 1, 1),
                       Vec3(-1, 1e-7f, -1), Vec3(0, 1e-9f, -1)})
    worst = std::max(worst, angle_deg(v, decode_normal(encode_normal(v))));
  EXPECT_LT(worst, kNormalErrorDegrees);
  EXPECT_GT(worst, 0.1f);  // 8 bits per coordinate cannot be exact
}

// Codes of the upper hemisphere come back exactly. Below it the octahedral fold does not
// map the lattice onto itself, so a code may come back as a neighbour, within the bound,
// and after one trip the code is stable.
TEST(CompactQuantize, EveryNormalCodeDecodesToAUnitVectorThatEncodesBack) {
  for (uint32_t c = 0; c < 65536; ++c) {
    const Vec3 d = decode_normal(uint16_t(c));
    ASSERT_NEAR(length(d), 1.0f, 1e-5f) << c;
    const uint16_t again = encode_normal(d);
    if (d.z > 1e-3f) {
      EXPECT_EQ(again, c) << c;
    }
    EXPECT_LT(angle_deg(decode_normal(again), d), kNormalErrorDegrees) << c;
    EXPECT_EQ(encode_normal(decode_normal(again)), again) << c;
  }
}

TEST(CompactQuantize, UvErrorIsHalfAStep) {
  const UvRange r = UvRange::fit(Vec2{-3, 0.25f}, Vec2{7, 0.5f});
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 20000; ++i) {
    const Vec2 t{-3 + 10 * u(rng), 0.25f + 0.25f * u(rng)};
    uint16_t q[2];
    encode_uv(r, t, q);
    const Vec2 d = decode_uv(r, q);
    EXPECT_LE(std::fabs(d.x - t.x), 0.5f * r.scale.x + 1e-6f);
    EXPECT_LE(std::fabs(d.y - t.y), 0.5f * r.scale.y + 1e-6f);
  }
}

// A sphere of many small triangles, with normals and uvs.
Scene sphere_scene() { return make_lit_sphere(0.8f, 48, 96, true); }

// Rays from around the scene towards points near random vertices of it.
std::vector<Ray> random_rays(const Scene& s, int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  const Bounds3 b = s.bounds();
  const float r = length(b.extent());
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    const Vec3 jitter = Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * (0.02f * r);
    const Vec3 target = s.positions[rng() % s.positions.size()] + jitter;
    const Vec3 org = b.center() + normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f)) * r;
    rays.push_back(Ray{org, normalize(target - org), 0.0f, INFINITY});
  }
  return rays;
}

// The quantized tree must be conservative: every hit Embree finds on the decoded
// triangles, the compact traversal finds too, at the same distance on the same triangle.
TEST(CompactTraversal, FindsTheHitsOfTheDecodedTriangles) {
  for (const Scene& scene : {make_cornell_box(), sphere_scene()}) {
    const CompactScene c = build_compact_scene(scene);
    Scene decoded = scene;
    for (uint32_t v = 0; v < decoded.positions.size(); ++v)
      decoded.positions[v] = c.mesh.position(v);
    const Accel embree(decoded);
    int hits = 0, same = 0, missed = 0, other = 0;
    for (const Ray& ray : random_rays(scene, 20000)) {
      Hit a, b;
      const bool ha = embree.intersect(ray, a), hb = compact_intersect(c, nullptr, ray, b);
      EXPECT_EQ(compact_occluded(c, nullptr, ray), hb);
      if (!ha) continue;
      ++hits;
      missed += !hb;
      other += hb && b.prim != a.prim;
      // Another triangle at the same distance is a tie (the Cornell box has coplanar
      // quads, and a ray through a shared edge may take either side).
      same += hb && std::fabs(b.t - a.t) <= 1e-4f * a.t;
    }
    std::printf("%s: %d hits, %d missed, %d on another triangle\n", scene.name.c_str(), hits,
                missed, other);
    ASSERT_GT(hits, 5000);
    // Embree's watertight test and our Moller-Trumbore may split a ray on a shared edge
    // differently: allow that, nothing more.
    EXPECT_GE(same, hits - hits / 500) << scene.name << ": " << same << " of " << hits;
  }
}

Scene one_triangle(Vec3 a, Vec3 b, Vec3 c) {
  Scene s = make_cornell_box();
  s.positions = {a, b, c};
  s.normals.clear(), s.uvs.clear();
  s.indices = {0, 1, 2};
  s.material_ids = {0};
  s.environment = Vec3(0.5f);
  return s;
}

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// All vertices equal: nothing can be hit, as at full precision (the same image).
TEST(CompactScene, DegenerateScenesRender) {
  const RenderSettings settings{.spp = 2, .max_bounces = 3};
  const Scene point = one_triangle(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1));
  EXPECT_TRUE(build_compact_scene(point).bvh.nodes.empty());
  EXPECT_TRUE(identical(
      testing::render_regions(point, 16, 16, settings, {{0, 0, 16, 16}}),
      testing::render_regions(point, 16, 16, settings, {{0, 0, 16, 16}}, 1, 1, 0, true)));
  // A flat scene and a single triangle: rendered, and close to full precision.
  Scene tri = one_triangle(Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0));
  tri.cameras = {Camera{{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 60}};
  const Framebuffer full = testing::render_regions(tri, 32, 32, settings, {{0, 0, 32, 32}});
  const Framebuffer small =
      testing::render_regions(tri, 32, 32, settings, {{0, 0, 32, 32}}, 1, 1, 0, true);
  EXPECT_GE(image_error(small, full).psnr_db, 40.0);
}

// The bound: PSNR >= 40 dB against the full-precision render with the same seeds.
// Paths use the same random numbers in both, but a path that meets an edge or a Russian
// roulette threshold differently continues elsewhere: that part of the difference is
// Monte Carlo noise and falls with the sample count (Cornell box: 32 dB at 8 spp, 40.3 at
// 64), so the images are compared at 128 spp.
TEST(CompactScene, ImagesAreWithinThePsnrBoundOfFullPrecision) {
  const RenderSettings settings{.spp = 128, .max_bounces = 4};
  for (const Scene& scene : {make_cornell_box(), sphere_scene()}) {
    const Framebuffer full = testing::render_regions(scene, 64, 48, settings, {{0, 0, 64, 48}});
    const Framebuffer small =
        testing::render_regions(scene, 64, 48, settings, {{0, 0, 64, 48}}, 1, 1, 0, true);
    EXPECT_FALSE(identical(full, small)) << scene.name;  // it is a different representation
    const ImageError e = image_error(small, full);
    std::printf("%s: PSNR %.1f dB\n", scene.name.c_str(), e.psnr_db);
    EXPECT_GE(e.psnr_db, 40.0) << scene.name;
  }
}

TEST(CompactScene, ImageDoesNotDependOnTheSplit) {
  const Scene scene = sphere_scene();
  const RenderSettings settings{.spp = 2, .max_bounces = 4};
  const Framebuffer one =
      testing::render_regions(scene, 61, 37, settings, {{0, 0, 61, 37}}, 1, 1, 0, true);
  const Framebuffer split = testing::render_regions(
      scene, 61, 37, settings, {{0, 0, 13, 37}, {13, 0, 61, 20}, {13, 20, 61, 37}}, 3, 2, 0, true);
  EXPECT_TRUE(identical(one, split));
}

TEST(CompactScene, IsSmallerThanFullPrecisionAndReportsItsBytes) {
  const Scene scene = sphere_scene();
  SceneCache cache(scene);
  const CpuDevice full(cache, CpuDeviceOptions{}, "cpu");
  const CpuDevice small(cache, CpuDeviceOptions{.compact = true}, "cpu:compact=1");
  EXPECT_EQ(full.info().representation, "embree");
  EXPECT_EQ(small.info().representation, "compact");
  EXPECT_GT(small.info().scene_bytes, 0u);
  EXPECT_LT(2 * small.info().scene_bytes, full.info().scene_bytes);
  const CompactScene& c = cache.compact_scene();
  EXPECT_LT(compact_bytes(c).total(), full_precision_bytes(scene, c.bvh.nodes.size()).total());
  // The estimates made before building are upper bounds of what is built.
  EXPECT_GE(estimate_compact_bytes(scene).total(), compact_bytes(c).total());
}

TEST(CompactScene, MemoryLimitRefusesWhatDoesNotFitUnlessCompactFits) {
  // A limit between what the sphere needs compact and at full precision.
  const Scene scene = make_lit_sphere(0.8f, 128, 256, true);
  SceneCache cache(scene);
  const uint64_t limit =
      (estimate_scene_bytes(scene, true) + estimate_scene_bytes(scene, false)) / 2;
  try {
    CpuDevice d(cache, CpuDeviceOptions{.memory_limit = limit}, "cpu:mem=1M");
    FAIL() << "a scene over the limit was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("emulated"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("compact=1 would need"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  const CpuDevice d(cache, CpuDeviceOptions{.compact = true, .memory_limit = limit},
                    "cpu:compact=1:mem=1M");
  EXPECT_LE(d.info().scene_bytes, limit);
}

}  // namespace compact_test
}  // namespace multiray
