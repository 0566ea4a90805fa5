// Emissive triangles as area lights, chosen in proportion to their power
// (area x luminance of emission; for an emission texture, its mean over four points of
// the triangle), for next-event estimation (render/shared/lights.h samples them). A
// sample's radiance is the texel's.
#pragma once

#include <vector>

#include "core/math.h"
#include "render/shared/scene_records.h"
#include "scene/scene.h"

namespace multiray {

class LightSampler {
 public:
  explicit LightSampler(const Scene& scene);

  bool empty() const { return tris_.empty(); }
  // Sum over the lights of area x luminance of emission (the power / pi of Lambertian
  // emitters), with the same texture estimate as the selection.
  double total_power() const { return total_power_; }
  // Area density with which sample() would have produced a point on triangle `prim`
  // (0 if it is not a light).
  float pdf_area(uint32_t prim) const;

  // The sampler's tables, for backends that sample lights themselves (OpenCL) and must
  // use the same distribution: emissive triangle indices, their cumulative selection
  // probabilities (last = 1) and, per scene triangle, selection probability / area.
  const std::vector<uint32_t>& triangles() const { return tris_; }
  const std::vector<float>& cdf() const { return cdf_; }
  const std::vector<float>& pdf_by_prim() const { return pdf_by_prim_; }
  // The emissive triangles as the integrator samples them (render/shared/lights.h), in
  // the order of cdf().
  const std::vector<LightRecord>& records() const { return records_; }

 private:
  Vec2 uv_at(uint32_t t, float b1, float b2) const;  // uv at barycentrics (b1, b2)
  Vec3 mean_emission(uint32_t t) const;

  const Scene& scene_;
  std::vector<uint32_t> tris_;      // emissive triangle indices
  std::vector<float> cdf_;          // cumulative power, last element = 1
  std::vector<float> pdf_by_prim_;  // per scene triangle, selection prob / area
  std::vector<LightRecord> records_;
  double total_power_ = 0;
};

}  // namespace multiray
