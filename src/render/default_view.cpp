#include "render/default_view.h"

#include <algorithm>
#include <cmath>

#include "render/path_tracer.h"

namespace multiray {

const std::vector<DefaultViewCandidate>& default_view_candidates() {
  static const std::vector<DefaultViewCandidate> views = {
      {kDefaultAzimuthDeg, kDefaultElevationDeg},           // three-quarter, front right
      {0.0f, 0.0f},                                         // straight at the front
      {180.0f, 0.0f},                                       // straight at the back
      {-kDefaultAzimuthDeg, kDefaultElevationDeg},          // front left
      {180.0f + kDefaultAzimuthDeg, kDefaultElevationDeg},  // back left
      {180.0f - kDefaultAzimuthDeg, kDefaultElevationDeg},  // back right
  };
  return views;
}

float front_face_share(const RenderScene& rs, const Camera& camera, float aspect, int nx, int ny) {
  // Any image of this aspect: only directions matter.
  const int h = 1000, w = std::max(1, int(float(h) * aspect));
  const PinholeCamera cam(camera, w, h);
  int hits = 0, front = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Ray ray = cam.ray((float(i) + 0.5f) * float(w) / float(nx),
                              (float(j) + 0.5f) * float(h) / float(ny));
      Hit hit;
      if (!rs.accel.intersect(ray, hit)) continue;
      ++hits;
      front += dot(hit.ng, ray.dir) < 0;
    }
  return hits > 0 ? float(front) / float(hits) : 0.0f;
}

Camera choose_default_camera(const RenderScene& rs, float aspect, Vec3 up) {
  std::vector<Camera> cams;
  std::vector<float> shares;
  for (const DefaultViewCandidate& v : default_view_candidates()) {
    cams.push_back(rs.scene.default_camera(aspect, up, v.azimuth_deg, v.elevation_deg));
    shares.push_back(front_face_share(rs, cams.back(), aspect));
  }
  const float best = *std::max_element(shares.begin(), shares.end());
  for (size_t i = 0; i < cams.size(); ++i)
    if (shares[i] >= best - kFrontShareSlack) return cams[i];
  return cams.front();
}

namespace {
// The scene's bounds in the frame of its up axis: unit world axes (`along` the longer
// horizontal side, `across` the shorter, `up` signed as given) and half extents.
struct UpFrame {
  Vec3 centre, along, across, up;
  float half_along = 0, half_across = 0, half_up = 0;
  // The point at (x, y, h) in [-1, 1]^3 of the box (h = -1: its bottom as `up` sees it).
  Vec3 at(float x, float y, float h) const {
    return centre + along * (x * half_along) + across * (y * half_across) + up * (h * half_up);
  }
};

UpFrame up_frame(const Bounds3& b, Vec3 up) {
  const int u = std::abs(up.x) > 0.5f ? 0 : std::abs(up.y) > 0.5f ? 1 : 2;
  const Vec3 half = b.extent() * 0.5f;
  int a = (u + 1) % 3, c = (u + 2) % 3;
  if (half[c] > half[a]) std::swap(a, c);
  UpFrame f;
  f.centre = b.center();
  f.along = f.across = f.up = Vec3(0.0f);
  f.along[a] = f.across[c] = 1.0f;
  f.up[u] = up[u] < 0 ? -1.0f : 1.0f;
  f.half_along = half[a], f.half_across = half[c], f.half_up = half[u];
  return f;
}

// The first hit of the ray from `org` along the unit `dir`: its distance (infinite when
// nothing is hit) and whether it is a front face.
struct Probe {
  float t = INFINITY;
  bool front = false;
};
Probe cast(const RenderScene& rs, Vec3 org, Vec3 dir) {
  Ray ray{org, dir};
  Hit hit;
  if (!rs.accel.intersect(ray, hit)) return {};
  return {hit.t, dot(hit.ng, dir) < 0};
}

// `n` directions round the horizon at each of the elevations -e, 0, +e degrees
// (e = kProbeElevationDeg), staggered so that no two rows repeat an azimuth.
std::vector<Vec3> horizon_directions(const UpFrame& f, int n) {
  std::vector<Vec3> dirs;
  for (int row = 0; row < 3; ++row) {
    const float el = float(row - 1) * kProbeElevationDeg * kPi / 180.0f;
    for (int i = 0; i < n; ++i) {
      const float az = 2.0f * kPi * (float(i) + float(row) / 3.0f) / float(n);
      dirs.push_back((f.along * std::cos(az) + f.across * std::sin(az)) * std::cos(el) +
                     f.up * std::sin(el));
    }
  }
  return dirs;
}
}  // namespace

InteriorProbe probe_interior(const RenderScene& rs, Vec3 up) {
  const Bounds3 b = rs.scene.bounds();
  const UpFrame f = up_frame(b, up);
  const std::vector<Vec3> dirs = horizon_directions(f, 24);
  const float tol = kSideTolerance * 2.0f * std::max(f.half_along, f.half_across);
  int rays = 0, hits = 0, front = 0, side = 0;
  // Six points along the long axis, low and at mid height (a room's air; a closed object's
  // inside and the space round it). A point whose hits are mostly back faces is inside a
  // solid (a column, a wall) and left out.
  for (float x : {-0.5f, 0.0f, 0.5f})
    for (float h : {-0.5f, 0.0f}) {
      const Vec3 org = f.at(x, 0.0f, h);
      int n = 0, nf = 0, ns = 0;
      for (Vec3 d : dirs) {
        const Probe p = cast(rs, org, d);
        if (!std::isfinite(p.t)) continue;
        ++n;
        nf += p.front;
        const Vec3 q = org + d * p.t - f.centre;
        ns += f.half_along - std::abs(dot(q, f.along)) < tol ||
              f.half_across - std::abs(dot(q, f.across)) < tol;
      }
      if (2 * nf < n) continue;
      rays += int(dirs.size()), hits += n, front += nf, side += ns;
    }
  InteriorProbe out;
  out.hit_share = rays > 0 ? float(hits) / float(rays) : 0.0f;
  out.front_share = hits > 0 ? float(front) / float(hits) : 0.0f;
  out.side_share = hits > 0 ? float(side) / float(hits) : 0.0f;
  const float aspect = 16.0f / 9.0f;  // the probe's own: only the share matters
  out.outside_front_share = front_face_share(rs, rs.scene.default_camera(aspect, up), aspect);
  return out;
}

bool is_interior(const InteriorProbe& p) {
  return p.hit_share >= kInteriorHitShare && p.front_share >= kInteriorFrontShare &&
         (p.outside_front_share >= 0.5f || p.side_share >= 0.5f);
}

namespace {
// Whether a camera at `eye` stands in free space: of rays along the 26 directions of a
// cube's faces, edges and corners, none hits nearer than `clearance` and at most two hit
// a back face (inside a column or a floor slab nearly all of them do).
bool is_free(const RenderScene& rs, Vec3 eye, float clearance) {
  int back = 0;
  for (int i = 0; i < 27; ++i) {
    const Vec3 d(float(i % 3) - 1.0f, float(i / 3 % 3) - 1.0f, float(i / 9) - 1.0f);
    if (i == 13) continue;  // (0, 0, 0)
    const Probe p = cast(rs, eye, normalize(d));
    if (p.t < clearance) return false;
    back += std::isfinite(p.t) && !p.front;
  }
  return back <= 2;
}

// Eye height above the floor, as a fraction of the floor-to-ceiling height.
constexpr float kEyeHeight = 0.25f;

// The eye above the floor under `p` (a front face straight below), or empty.
std::optional<Vec3> eye_over_floor(const RenderScene& rs, const UpFrame& f, Vec3 p) {
  const Probe floor = cast(rs, p, -f.up);
  if (!floor.front) return std::nullopt;
  const Vec3 on_floor = p - f.up * floor.t;
  const float to_top = dot(f.at(0, 0, 1) - on_floor, f.up);
  const Vec3 start = on_floor + f.up * (1e-4f * to_top);
  const float room = std::min(to_top, cast(rs, start, f.up).t);
  return on_floor + f.up * (kEyeHeight * room);
}
}  // namespace

std::optional<Camera> interior_camera(const RenderScene& rs, Vec3 up) {
  const Bounds3 b = rs.scene.bounds();
  const UpFrame f = up_frame(b, up);
  const float clearance = 0.02f * length(b.extent());
  // Spots near either end of the long axis looking towards the other, from the middle of
  // the short axis outwards. The first whose view is open (kOpenView of the way to the
  // far side of the bounds) is taken, else the most open one.
  constexpr float kOpenView = 0.9f;
  std::optional<Camera> best;
  float best_open = 0.0f;
  std::vector<std::pair<float, float>> spots;  // (x, y) for UpFrame::at, in that order
  for (float y : {0.0f, -0.3f, 0.3f, -0.6f, 0.6f})
    for (float x : {-0.7f, 0.7f, -0.5f, 0.5f, -0.3f, 0.3f}) spots.emplace_back(x, y);
  for (auto [x, y] : spots) {
    const std::optional<Vec3> eye = eye_over_floor(rs, f, f.at(x, y, 0.0f));
    if (!eye || !is_free(rs, *eye, clearance)) continue;
    const Vec3 dir = f.along * (x < 0 ? 1.0f : -1.0f);
    const float to_side = dot(f.at(x < 0 ? 1.0f : -1.0f, 0, 0) - *eye, dir);
    const float view = std::min(cast(rs, *eye, dir).t, to_side);
    if (best && view <= best_open * to_side) continue;
    Camera c;
    c.eye = *eye;
    c.up = f.up;
    c.fov_y_deg = kInteriorFovDeg;
    // An orbit about the target keeps within the short side's half width.
    const float r = std::min(0.5f * view, 0.9f * f.half_across * (1.0f - std::abs(y)));
    c.target = *eye + dir * std::max(r, 1e-3f * clearance);
    best = c, best_open = view / to_side;
    if (best_open >= kOpenView) break;
  }
  return best;
}

DefaultView choose_default_view(const RenderScene& rs, float aspect, Vec3 up) {
  if (is_interior(probe_interior(rs, up)))
    if (const std::optional<Camera> inside = interior_camera(rs, up))
      return {*inside, "default-interior"};
  return {choose_default_camera(rs, aspect, up), "default"};
}

Camera default_volume_camera(const Scene& scene, float aspect, Vec3 up, Vec3 front) {
  // front's azimuth in view_direction's frame (0 for view_direction's own front).
  const float ahead = dot(front, view_direction(up, 0, 0)),
              right = dot(front, view_direction(up, 90, 0));
  const float turn =
      std::abs(ahead) + std::abs(right) > 0.5f ? std::atan2(right, ahead) * 180.0f / kPi : 0.0f;
  return scene.default_camera(aspect, up, turn + kDefaultAzimuthDeg, kDefaultElevationDeg);
}

float share_outside_frame(const Scene& scene, const Camera& camera, float aspect,
                          size_t max_points) {
  const size_t n = scene.positions.size();
  if (n == 0 || max_points == 0) return 0;
  const Bounds3 b = scene.bounds();
  const Vec3 e = camera.eye;
  if (!b.empty() && e.x >= b.lo.x && e.x <= b.hi.x && e.y >= b.lo.y && e.y <= b.hi.y &&
      e.z >= b.lo.z && e.z <= b.hi.z)
    return 0;
  const Vec3 f = normalize(camera.target - camera.eye);
  const Vec3 r = normalize(cross(f, camera.up));
  const Vec3 u = cross(r, f);
  const float tan_y = std::tan(0.5f * camera.fov_y_deg * float(kPi) / 180.0f);
  const float tan_x = tan_y * aspect;
  const size_t stride = std::max<size_t>(1, n / max_points);
  size_t seen = 0, outside = 0;
  for (size_t i = 0; i < n; i += stride, ++seen) {
    const Vec3 d = scene.positions[i] - e;
    const float z = dot(d, f);
    if (!(z > 0) || std::abs(dot(d, r)) > tan_x * z || std::abs(dot(d, u)) > tan_y * z) ++outside;
  }
  return float(outside) / float(seen);
}

}  // namespace multiray
