#include "render/reprojection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/path_tracer.h"

namespace multiray {

namespace {

// A pinhole camera that also projects: world point -> image position (pixels, y down)
// and view-space depth, the inverse of PinholeCamera::ray at that depth.
struct Projector {
  Projector(const ViewSetup& v)
      : cam(v.camera, v.width, v.height), width(v.width), height(v.height) {}

  // The world point seen through image position (px, py) at view-space depth `depth`.
  Vec3 point(float px, float py, float depth) const {
    const Ray r = cam.ray(px, py);
    return r.org + r.dir * (depth / dot(r.dir, cam.forward));
  }
  // False behind the camera. Otherwise (px, py) may lie outside the image.
  bool project(const Vec3& p, float& px, float& py, float& depth) const {
    const Vec3 d = p - cam.eye;
    depth = dot(d, cam.forward);
    if (!(depth > 0)) return false;
    const float sx = dot(d, cam.right) / (depth * cam.scale_x);
    const float sy = dot(d, cam.up) / (depth * cam.scale_y);
    px = 0.5f * (sx + 1.0f) * float(width);
    py = 0.5f * (1.0f - sy) * float(height);
    return true;
  }
  // The pixel containing image position (px, py), or -1 outside the image.
  int64_t pixel(float px, float py) const {
    if (!(px >= 0 && py >= 0 && px < float(width) && py < float(height))) return -1;
    return int64_t(py) * width + int64_t(px);
  }

  PinholeCamera cam;
  int width, height;
};

bool same_surface(float a, float b, float tolerance) {
  return std::isfinite(a) && std::isfinite(b) && std::abs(a - b) <= tolerance * std::min(a, b);
}

// Forward warp: every reference pixel with a hit goes to the target pixel its surface
// point projects into; the nearest wins. Fills `depth` (target view space) and `source`.
void splat(const GBuffer& g, const Projector& ref, const Projector& tgt, std::vector<float>& depth,
           std::vector<int32_t>& source) {
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * size_t(g.width) + size_t(x);
      if (!std::isfinite(g.depth[i])) continue;
      const Vec3 p = ref.point(float(x) + 0.5f, float(y) + 0.5f, g.depth[i]);
      float px, py, z;
      if (!tgt.project(p, px, py, z)) continue;
      const int64_t t = tgt.pixel(px, py);
      if (t < 0 || !(z < depth[size_t(t)])) continue;
      depth[size_t(t)] = z;
      source[size_t(t)] = int32_t(i);
    }
}

// The reference pixel a crack at target pixel (x, y), between neighbours `a` and `b` of
// the forward warp, takes: the one seen at the depth between them, if the reference sees
// that surface there. ReprojectionMap::kHole otherwise.
int32_t close_crack(const GBuffer& g, const Projector& ref, const Projector& tgt, int x, int y,
                    float za, float zb, float tolerance) {
  if (!same_surface(za, zb, tolerance)) return ReprojectionMap::kHole;
  const Vec3 p = tgt.point(float(x) + 0.5f, float(y) + 0.5f, 0.5f * (za + zb));
  float px, py, z;
  if (!ref.project(p, px, py, z)) return ReprojectionMap::kHole;
  const int64_t r = ref.pixel(px, py);
  if (r < 0 || !same_surface(g.depth[size_t(r)], z, tolerance)) return ReprojectionMap::kHole;
  return int32_t(r);
}

}  // namespace

size_t ReprojectionMap::holes() const {
  return size_t(std::count(source.begin(), source.end(), kHole));
}

ReprojectionMap reproject_view(const GBuffer& reference_depth, const ViewSetup& reference,
                               const ViewSetup& target, const ReprojectionOptions& o) {
  if (reference.width != target.width || reference.height != target.height ||
      reference_depth.width != reference.width || reference_depth.height != reference.height)
    throw std::invalid_argument("reproject_view: the views and the G-buffer differ in size");
  const Projector ref(reference), tgt(target);
  const size_t w = size_t(target.width), n = w * size_t(target.height);
  std::vector<float> depth(n, INFINITY);
  ReprojectionMap m;
  m.width = target.width, m.height = target.height;
  m.source.assign(n, ReprojectionMap::kHole);
  splat(reference_depth, ref, tgt, depth, m.source);

  // Cracks are judged on the warp alone (`depth` is not updated), so the order of the
  // scan does not matter.
  for (int y = 0; y < target.height; ++y)
    for (int x = 0; x < target.width; ++x) {
      const size_t i = size_t(y) * w + size_t(x);
      if (m.source[i] != ReprojectionMap::kHole) continue;
      if (x > 0 && x + 1 < target.width)
        m.source[i] = close_crack(reference_depth, ref, tgt, x, y, depth[i - 1], depth[i + 1],
                                  o.depth_tolerance);
      if (m.source[i] == ReprojectionMap::kHole && y > 0 && y + 1 < target.height)
        m.source[i] = close_crack(reference_depth, ref, tgt, x, y, depth[i - w], depth[i + w],
                                  o.depth_tolerance);
    }
  return m;
}

std::vector<uint8_t> hole_sample_map(const ReprojectionMap& map, int spp) {
  if (spp < 1 || spp > 255) throw std::invalid_argument("hole_sample_map: spp must be 1..255");
  std::vector<uint8_t> out(map.source.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = map.source[i] == ReprojectionMap::kHole ? uint8_t(spp) : uint8_t(0);
  return out;
}

void fill_reprojected(const Framebuffer& reference, const ReprojectionMap& map,
                      Framebuffer& target) {
  if (reference.width != map.width || reference.height != map.height ||
      target.width != map.width || target.height != map.height)
    throw std::invalid_argument("fill_reprojected: the images and the map differ in size");
  for (size_t i = 0; i < map.source.size(); ++i)
    if (map.source[i] != ReprojectionMap::kHole)
      target.pixels[i] = reference.pixels[size_t(map.source[i])];
}

void ReprojectedFrame::fill(std::vector<Framebuffer>& images) const {
  if (images.size() != maps.size() || reference >= images.size())
    throw std::invalid_argument("ReprojectedFrame::fill: one image per view expected");
  for (size_t v = 0; v < images.size(); ++v)
    if (v != reference) fill_reprojected(images[reference], maps[v], images[v]);
}

double ReprojectedFrame::hole_fraction() const {
  size_t holes = 0, pixels = 0;
  for (size_t v = 0; v < maps.size(); ++v)
    if (v != reference) holes += maps[v].holes(), pixels += maps[v].source.size();
  return pixels ? double(holes) / double(pixels) : 0.0;
}

}  // namespace multiray
