#include "render/shading_data.h"

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

}  // namespace multiray
