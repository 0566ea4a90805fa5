// Accel's batched shadow queries (render/accel.h) against its one-ray query.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "render/accel.h"
#include "render/compact_scene.h"
#include "scene/builders.h"

namespace multiray {
namespace {

// Rays from inside the Cornell box in every direction, some short (ending before the
// walls), others long; one material a stochastic cut-out, so the filter runs on packets.
std::vector<Ray> rays_in(const Scene& s, int n) {
  const Bounds3 b = s.bounds();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    const Vec3 o =
        b.lo + b.extent() * Vec3(0.1f + 0.8f * u(rng), 0.1f + 0.8f * u(rng), 0.1f + 0.8f * u(rng));
    const Vec3 d = normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
    const float tmax = i % 3 == 0 ? 0.05f * max_component(b.extent()) : INFINITY;
    rays.push_back(Ray{o, d, 0.0f, tmax});
  }
  return rays;
}

// Every ray gets occluded()'s answer, in batches of every size from 1 to 19 (whole
// packets of eight and partial ones), on Embree's tree and on the compact scene's.
TEST(Accel, BatchedShadowQueriesAnswerEachRayAsOneRayQueriesDo) {
  Scene s = make_cornell_box();
  s.materials[0].alpha_mode = AlphaMode::blend;
  s.materials[0].opacity = 0.5f;
  const std::vector<Ray> rays = rays_in(s, 3000);
  const CompactScene compact = build_compact_scene(s);
  for (const bool on_compact : {false, true}) {
    const Accel accel(s, on_compact ? &compact : nullptr);
    std::vector<uint8_t> blocked(rays.size(), 2);
    for (size_t first = 0, size = 1; first < rays.size(); first += size, size = size % 19 + 1) {
      const size_t n = std::min(size, rays.size() - first);
      accel.occluded_batch(&rays[first], n, &blocked[first]);
    }
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(blocked[i], accel.occluded(rays[i]) ? 1 : 0) << "ray " << i << " " << on_compact;
      hits += blocked[i];
    }
    // Both answers occur (a test of nothing otherwise).
    EXPECT_GT(hits, 300) << on_compact;
    EXPECT_LT(hits, 2900) << on_compact;
  }
}

}  // namespace
}  // namespace multiray
