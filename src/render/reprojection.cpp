#include "render/reprojection.h"

#include <algorithm>
#include <climits>
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

// Cosine above which two neighbours' normals are one plane's (about 5.7 degrees).
constexpr float kSameNormal = 0.995f;

bool same_surface(float a, float b, float tolerance) {
  return std::isfinite(a) && std::isfinite(b) && std::abs(a - b) <= tolerance * std::min(a, b);
}

// Where a reference pixel's surface point lands in the target: image position, target
// view-space depth; ok false for misses and points behind the target.
struct Landing {
  float x = 0, y = 0, z = INFINITY;
  bool ok = false;
};

// The target's depth buffer and sources as the warp fills them: the nearest wins. After
// the first reference, a pixel changes hands only to a surface nearer by more than
// `margin` (a fraction of its depth): the same surface seen by a farther reference keeps
// the nearer reference's colour (view-dependent shading is closer to the target's).
struct Warp {
  int width, height;
  std::vector<float> depth;
  std::vector<int32_t>& source;
  float margin = 0;
  void offer(int64_t pixel, float z, int32_t from) {
    if (pixel < 0 || !(z < depth[size_t(pixel)] * (1.0f - margin))) return;
    depth[size_t(pixel)] = z;
    source[size_t(pixel)] = from;
  }
};

// The target pixels whose centres lie between the landings of neighbouring reference
// pixels a and b on one surface, along x (`along_x`) or y: what a surface seen at a slant
// spreads over in the target beyond its pixels' own landings. The segment from a to b is
// walked one pixel centre at a time along its axis; across it, each step takes the row
// (or column) the segment crosses there, so pairs that drift into the next row, as in
// diagonal views, still fill. Each pixel takes the nearer end's source and the
// interpolated depth. Spans longer than kMaxSpan pixels, or drifting more than one pixel
// across, are left as holes (on one surface, adjacent pixels' disparities differ by the
// depth tolerance at most).
void fill_span(const Landing& a, int32_t ia, const Landing& b, int32_t ib, bool along_x, Warp& w) {
  constexpr float kMaxSpan = 4.0f;
  const float a0 = along_x ? a.x : a.y, b0 = along_x ? b.x : b.y;
  const float a1 = along_x ? a.y : a.x, b1 = along_x ? b.y : b.x;
  if (!(std::abs(b0 - a0) <= kMaxSpan) || !(std::abs(b1 - a1) <= 1.0f)) return;
  const float lo = std::min(a0, b0), hi = std::max(a0, b0);
  const int limit = along_x ? w.width : w.height, across_limit = along_x ? w.height : w.width;
  for (int c = std::max(0, int(std::ceil(lo - 0.5f))); c < limit && float(c) + 0.5f <= hi; ++c) {
    const float t = b0 != a0 ? (float(c) + 0.5f - a0) / (b0 - a0) : 0.0f;
    const float line = std::floor(a1 + t * (b1 - a1));
    if (line < 0 || line >= float(across_limit)) continue;
    const float z = a.z + t * (b.z - a.z);
    const int64_t pixel =
        along_x ? int64_t(line) * w.width + c : int64_t(c) * w.width + int64_t(line);
    w.offer(pixel, z, t < 0.5f ? ia : ib);
  }
}

}  // namespace

bool project_to_image(const ViewSetup& view, const Vec3& p, float& px, float& py) {
  float depth;
  return Projector(view).project(p, px, py, depth);
}

size_t ReprojectionMap::holes() const {
  return size_t(std::count(source.begin(), source.end(), kHole));
}

ReferenceSurface prepare_reference(const GBuffer& depth, const ViewSetup& view,
                                   const ReprojectionOptions& o) {
  if (depth.width != view.width || depth.height != view.height)
    throw std::invalid_argument("prepare_reference: the view and its G-buffer differ in size");
  ReferenceSurface r;
  r.view = &view;
  const GBuffer& g = depth;
  const Projector ref(view);
  const size_t w = size_t(g.width), n = w * size_t(g.height);
  r.point.resize(n);
  r.flags.assign(n, 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * w + size_t(x);
      if (!std::isfinite(g.depth[i])) continue;
      r.point[i] = ref.point(float(x) + 0.5f, float(y) + 0.5f, g.depth[i]);
      r.flags[i] = ReferenceSurface::kHit;
    }
  // One surface: depths within the tolerance, or (for planes seen at a grazing angle, whose
  // depth changes fast from pixel to pixel) the same normal and the step between the two
  // points lying in the plane, its height over it at most the tolerance of its length.
  const auto joined = [&](size_t i, size_t j) {
    if (!(r.flags[i] & r.flags[j] & ReferenceSurface::kHit)) return false;
    if (same_surface(g.depth[i], g.depth[j], o.depth_tolerance)) return true;
    const Vec3 step = r.point[j] - r.point[i];
    return dot(g.normal[i], g.normal[j]) >= kSameNormal &&
           std::abs(dot(step, g.normal[i])) <= o.depth_tolerance * length(step);
  };
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * w + size_t(x);
      if (x + 1 < g.width && joined(i, i + 1)) r.flags[i] |= ReferenceSurface::kJoinedRight;
      if (y + 1 < g.height && joined(i, i + w)) r.flags[i] |= ReferenceSurface::kJoinedBelow;
    }
  return r;
}

namespace {
// Warps one reference into `warp`: every surface point to the pixel it lands in, then the
// spans between neighbours on one surface. Its pixel i is source `offset + i`.
void warp_reference(const ReferenceSurface& r, const Projector& tgt, int32_t offset, Warp& warp) {
  const int width = r.view->width, height = r.view->height;
  const size_t w = size_t(width), n = w * size_t(height);
  std::vector<Landing> land(n);
  for (size_t i = 0; i < n; ++i) {
    if (!(r.flags[i] & ReferenceSurface::kHit)) continue;
    Landing& l = land[i];
    l.ok = tgt.project(r.point[i], l.x, l.y, l.z);
    if (l.ok) warp.offer(tgt.pixel(l.x, l.y), l.z, offset + int32_t(i));
  }
  for (size_t i = 0; i < n; ++i) {
    if (!land[i].ok) continue;
    const int32_t si = offset + int32_t(i);
    if ((r.flags[i] & ReferenceSurface::kJoinedRight) && land[i + 1].ok)
      fill_span(land[i], si, land[i + 1], si + 1, true, warp);
    if ((r.flags[i] & ReferenceSurface::kJoinedBelow) && land[i + w].ok)
      fill_span(land[i], si, land[i + w], si + int32_t(w), false, warp);
  }
}
}  // namespace

ReprojectionMap reproject_view(const std::vector<const ReferenceSurface*>& references,
                               const ViewSetup& target, const ReprojectionOptions& o) {
  const size_t n = size_t(target.width) * size_t(target.height);
  if (references.empty() || n * references.size() > size_t(INT32_MAX))
    throw std::invalid_argument("reproject_view: 1 reference or more, 2^31 pixels at most");
  for (const ReferenceSurface* r : references)
    if (r->view->width != target.width || r->view->height != target.height)
      throw std::invalid_argument("reproject_view: the views differ in size");
  ReprojectionMap m;
  m.width = target.width, m.height = target.height;
  m.source.assign(n, ReprojectionMap::kHole);
  Warp warp{target.width, target.height, std::vector<float>(n, INFINITY), m.source};
  const Projector tgt(target);
  for (size_t k = 0; k < references.size(); ++k) {
    warp.margin = k == 0 ? 0.0f : o.depth_tolerance;
    warp_reference(*references[k], tgt, int32_t(k * n), warp);
  }
  return m;
}

ReprojectionMap reproject_view(const GBuffer& reference_depth, const ViewSetup& reference,
                               const ViewSetup& target, const ReprojectionOptions& o) {
  const ReferenceSurface r = prepare_reference(reference_depth, reference, o);
  return reproject_view({&r}, target, o);
}

std::vector<uint8_t> hole_sample_map(const ReprojectionMap& map, int spp) {
  if (spp < 1 || spp > 255) throw std::invalid_argument("hole_sample_map: spp must be 1..255");
  std::vector<uint8_t> out(map.source.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = map.source[i] == ReprojectionMap::kHole ? uint8_t(spp) : uint8_t(0);
  return out;
}

void fill_reprojected(const std::vector<const Framebuffer*>& references,
                      const ReprojectionMap& map, Framebuffer& target) {
  const size_t n = map.source.size();
  for (const Framebuffer* r : references)
    if (r->width != map.width || r->height != map.height)
      throw std::invalid_argument("fill_reprojected: the images and the map differ in size");
  if (target.width != map.width || target.height != map.height)
    throw std::invalid_argument("fill_reprojected: the images and the map differ in size");
  for (size_t i = 0; i < n; ++i) {
    const int32_t s = map.source[i];
    if (s == ReprojectionMap::kHole) continue;
    if (size_t(s) / n >= references.size())
      throw std::invalid_argument("fill_reprojected: a source names a missing reference");
    target.pixels[i] = references[size_t(s) / n]->pixels[size_t(s) % n];
  }
}

bool ReprojectedFrame::is_reference(size_t view) const {
  return std::find(references.begin(), references.end(), uint32_t(view)) != references.end();
}

void ReprojectedFrame::fill(std::vector<Framebuffer>& images) const {
  if (images.size() != maps.size())
    throw std::invalid_argument("ReprojectedFrame::fill: one image per view expected");
  std::vector<const Framebuffer*> refs;
  for (uint32_t r : references) {
    if (r >= images.size()) throw std::invalid_argument("ReprojectedFrame::fill: no such view");
    refs.push_back(&images[r]);
  }
  for (size_t v = 0; v < images.size(); ++v)
    if (!is_reference(v)) fill_reprojected(refs, maps[v], images[v]);
}

double ReprojectedFrame::hole_fraction() const {
  size_t holes = 0, pixels = 0;
  for (size_t v = 0; v < maps.size(); ++v)
    if (!is_reference(v)) holes += maps[v].holes(), pixels += maps[v].source.size();
  return pixels ? double(holes) / double(pixels) : 0.0;
}

}  // namespace multiray
