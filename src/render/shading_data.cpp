#include "render/shading_data.h"

#include "render/compact_scene.h"

#include <algorithm>
#include <cmath>

namespace multiray {

std::vector<TriangleShading> build_shading_data(const Scene& s) {
  std::vector<TriangleShading> out(s.triangle_count());
  for (size_t t = 0; t < out.size(); ++t) {
    const uint32_t* idx = &s.indices[3 * t];
    TriangleShading& r = out[t];
    const Vec3 face = normalize(cross(s.positions[idx[1]] - s.positions[idx[0]],
                                      s.positions[idx[2]] - s.positions[idx[0]]));
    for (int k = 0; k < 3; ++k) {
      r.normal[k] = s.normals.empty() ? face : s.normals[idx[k]];
      r.uv[k] = s.uvs.empty() ? Vec2{} : s.uvs[idx[k]];
    }
    r.material = s.material_ids[t];
  }
  return out;
}

TriangleShading decode_shading(const CompactScene& c, uint32_t prim) {
  const CompactMeshView m = c.view();
  TriangleShading r;
  compact_shading(&m, prim, r.normal, r.uv, &r.material);
  return r;
}

std::vector<TriangleTangent> build_tangents(const Scene& s) {
  const bool any = std::any_of(s.materials.begin(), s.materials.end(),
                               [](const Material& m) { return m.normal_texture >= 0; });
  if (!any || s.uvs.empty()) return {};
  std::vector<TriangleTangent> out(s.triangle_count());
  for (size_t t = 0; t < out.size(); ++t) {
    const uint32_t* idx = &s.indices[3 * t];
    const Vec3 e1 = s.positions[idx[1]] - s.positions[idx[0]];
    const Vec3 e2 = s.positions[idx[2]] - s.positions[idx[0]];
    const Vec2 a = s.uvs[idx[0]], b = s.uvs[idx[1]], c = s.uvs[idx[2]];
    const float du1 = b.x - a.x, dv1 = b.y - a.y, du2 = c.x - a.x, dv2 = c.y - a.y;
    const float det = du1 * dv2 - du2 * dv1;
    if (!(std::abs(det) > 1e-12f)) continue;
    // Solve e1 = du1 dp/du + dv1 dp/dv, e2 = du2 dp/du + dv2 dp/dv.
    const Vec3 dpdu = (e1 * dv2 - e2 * dv1) / det;
    const Vec3 dpdv = (e2 * du1 - e1 * du2) / det;
    const float len = length(dpdu);
    if (!(len > 0) || !is_finite(dpdu) || !is_finite(dpdv)) continue;
    out[t].u = dpdu / len;
    out[t].sign = dot(cross(cross(e1, e2), dpdu), dpdv) < 0 ? 1.0f : -1.0f;
  }
  return out;
}

}  // namespace multiray
