#include "render/gbuffer.h"

#include <cmath>

#include <tbb/parallel_for.h>

#include "render/path_tracer.h"

namespace multiray {

GBuffer render_gbuffer(const RenderScene& rs, const ViewSetup& view) {
  GBuffer g;
  g.width = view.width, g.height = view.height;
  const size_t n = size_t(view.width) * size_t(view.height);
  g.depth.assign(n, INFINITY);
  g.normal.assign(n, Vec3(0.0f));
  const PinholeCamera camera(view.camera, view.width, view.height);
  // Rows in parallel: each pixel is written by one task and depends on nothing else.
  tbb::parallel_for(0, view.height, [&](int y) {
    for (int x = 0; x < view.width; ++x) {
      const Ray r = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      Hit hit;
      if (!rs.accel.intersect(r, hit)) continue;
      const size_t i = size_t(y) * size_t(view.width) + size_t(x);
      g.depth[i] = hit.t * dot(r.dir, camera.forward);
      const Vec3 nrm = normalize(hit.ng);
      g.normal[i] = dot(nrm, r.dir) > 0 ? -nrm : nrm;
    }
  });
  return g;
}

namespace {
bool surfaces_differ(const GBuffer& g, size_t a, size_t b, const EdgeOptions& o) {
  const bool ha = std::isfinite(g.depth[a]), hb = std::isfinite(g.depth[b]);
  if (ha != hb) return true;
  return ha && dot(g.normal[a], g.normal[b]) < o.normal_tolerance;
}

// 1/depth at `i`'s neighbours `a` and `b` bends away from the line through them.
bool depth_bends(const GBuffer& g, size_t a, size_t i, size_t b, const EdgeOptions& o) {
  if (!std::isfinite(g.depth[a]) || !std::isfinite(g.depth[i]) || !std::isfinite(g.depth[b]))
    return false;  // handled as a hit/miss edge
  const float ia = 1.0f / g.depth[a], ii = 1.0f / g.depth[i], ib = 1.0f / g.depth[b];
  return std::abs(ia - 2.0f * ii + ib) > o.depth_tolerance * ii;
}
}  // namespace

std::vector<uint8_t> detect_edges(const GBuffer& g, const EdgeOptions& o) {
  std::vector<uint8_t> edge(g.depth.size(), 0);
  const size_t w = size_t(g.width);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * w + size_t(x);
      if (x + 1 < g.width && surfaces_differ(g, i, i + 1, o)) edge[i] = edge[i + 1] = 1;
      if (y + 1 < g.height && surfaces_differ(g, i, i + w, o)) edge[i] = edge[i + w] = 1;
      if (x > 0 && x + 1 < g.width && depth_bends(g, i - 1, i, i + 1, o)) edge[i] = 1;
      if (y > 0 && y + 1 < g.height && depth_bends(g, i - w, i, i + w, o)) edge[i] = 1;
    }
  return edge;
}

std::vector<uint8_t> edge_sample_map(const std::vector<uint8_t>& edges, int edge_spp,
                                     int base_spp) {
  std::vector<uint8_t> map(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) map[i] = uint8_t(edges[i] ? edge_spp : base_spp);
  return map;
}

}  // namespace multiray
