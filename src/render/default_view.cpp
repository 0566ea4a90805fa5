#include "render/default_view.h"

#include <algorithm>

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

}  // namespace multiray
