// Ambient occlusion and adaptive edge sampling (the workloads of Harada, GPU Pro 7 ch. 4;
// edge sampling after Mitchell 1987).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "render/ambient_occlusion.h"
#include "render/gbuffer.h"
#include "render_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace irregular_test {

Framebuffer render_ao(const Scene& scene, int w, int h, RenderSettings s,
                      const std::vector<uint8_t>* map = nullptr, Rect rect = {}) {
  const RenderScene rs(scene);
  const AmbientOcclusion ao(rs);
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = w, v.height = h, v.spp_map = map;
  Framebuffer fb(w, h);
  if (rect.area() == 0) rect = {0, 0, w, h};
  ao.render_rect(v, s, rect, fb);
  return fb;
}

// A plane under an open sky is never occluded; inside a closed sphere every occlusion ray
// longer than the diameter hits: the answers are exactly 1 and 0.
TEST(AmbientOcclusion, KnownAnswersOpenPlaneAndClosedSphere) {
  RenderSettings s;
  s.kernel = "ao";
  s.spp = 4;
  s.ao_rays = 4;
  s.ao_distance = 5.0f;
  for (const Vec3& p : render_ao(make_lit_plane(0.5f, 1.0f), 16, 12, s).pixels)
    ASSERT_EQ(p.x, 1.0f);
  for (const Vec3& p : render_ao(make_furnace_sphere(0.5f, 1.0f), 16, 12, s).pixels)
    ASSERT_EQ(p.x, 0.0f);
}

// Corners of the Cornell box are darker than the middle of the back wall.
TEST(AmbientOcclusion, CornersAreDarkerThanOpenWalls) {
  RenderSettings s;
  s.spp = 64;
  s.ao_rays = 2;
  s.ao_distance = 0.5f;
  const Framebuffer fb = render_ao(make_cornell_box(), 64, 64, s);
  float corner = 0, middle = 0;
  for (int d = 0; d < 3; ++d) corner += fb.at(4 + d, 60 - d).x, middle += fb.at(30 + d, 20 + d).x;
  EXPECT_LT(corner, middle - 0.3f);
}

// A synthetic depth map: a near square on a far background. Edges are exactly the pixels
// on both sides of the square's border; the flat interior and background are not edges.
TEST(EdgeDetector, MarksBothSidesOfADepthStep) {
  GBuffer g;
  g.width = 8, g.height = 6;
  g.depth.assign(48, 10.0f);
  g.normal.assign(48, Vec3(0, 0, 1));
  for (int y = 2; y < 4; ++y)
    for (int x = 3; x < 6; ++x) g.depth[size_t(y * 8 + x)] = 5.0f;
  const auto e = detect_edges(g);
  auto at = [&](int x, int y) { return e[size_t(y * 8 + x)]; };
  EXPECT_EQ(at(0, 0), 0);
  EXPECT_EQ(at(2, 2), 1);  // background next to the square
  EXPECT_EQ(at(3, 2), 1);  // square border
  EXPECT_EQ(at(4, 1), 1);
  EXPECT_EQ(at(7, 5), 0);
  int count = 0;
  for (uint8_t v : e) count += v;
  EXPECT_EQ(count, 6 + 10);  // 6 square pixels (all on its border) + 10 neighbours outside
  // A crease (same depth, normals 90 degrees apart) is an edge too; a miss next to a hit is.
  g.depth.assign(48, 10.0f);
  g.normal.assign(48, Vec3(0, 0, 1));
  g.normal[10] = Vec3(1, 0, 0);
  g.depth[40] = INFINITY;
  const auto e2 = detect_edges(g);
  EXPECT_EQ(e2[10], 1);
  EXPECT_EQ(e2[11], 1);
  EXPECT_EQ(e2[40], 1);
  EXPECT_EQ(e2[41], 1);
  EXPECT_EQ(e2[20], 0);
}

// With a sample map, pixels take their own sample count, and the result still does not
// depend on how the rectangle was split.
TEST(AdaptiveSampling, SampleMapIsHonouredAndSplitIndependent) {
  const Scene scene = make_cornell_box();
  const RenderScene rs(scene);
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = 40, v.height = 30;
  const auto map = edge_sample_map(detect_edges(render_gbuffer(rs, v)), 5, 1);
  int edges = 0;
  for (uint8_t m : map) edges += m == 5;
  EXPECT_GT(edges, 40);   // the box has plenty of edges
  EXPECT_LT(edges, 600);  // but most pixels are not on one
  RenderSettings s;
  s.kernel = "ao";
  const Framebuffer whole = render_ao(scene, 40, 30, s, &map);
  Framebuffer parts = render_ao(scene, 40, 30, s, &map, {0, 0, 40, 13});
  const Framebuffer lower = render_ao(scene, 40, 30, s, &map, {0, 13, 40, 30});
  for (int y = 13; y < 30; ++y)
    for (int x = 0; x < 40; ++x) parts.at(x, y) = lower.at(x, y);
  EXPECT_EQ(
      std::memcmp(whole.pixels.data(), parts.pixels.data(), whole.pixels.size() * sizeof(Vec3)),
      0);
  // Samples reported = sum of the map.
  const AmbientOcclusion ao(rs);
  Framebuffer fb(40, 30);
  v.spp_map = &map;
  const KernelStats ks = ao.render_rect(v, s, {0, 0, 40, 30}, fb);
  EXPECT_EQ(ks.samples, uint64_t(30 * 40 - edges + 5 * edges));
}

}  // namespace irregular_test
}  // namespace multiray
