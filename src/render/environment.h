// Light from outside the scene: the constant sky (Scene::environment), an equirectangular
// radiance map and a sun, as one light for next-event estimation with multiple importance
// sampling (Veach 1997, power heuristic) against the BSDF.
//
// Sampling, per shading point with geometric normal n:
// - the sun, with probability 1/2 when there is also a sky (1 when only a sun): uniform in
//   its cone;
// - the sky: with a map, in proportion to luminance x sin(theta) of the map (constant sky
//   added), a piecewise-constant 2D distribution over its pixels (Pharr, Jakob & Humphreys,
//   PBR 3rd ed., §13.6.7 / §14.2.4); with the constant sky alone, cosine-weighted around n.
//   The cosine choice keeps a diffuse surface under a uniform sky at zero variance (both
//   techniques then have the same density) while a point that sees the sky only through
//   an opening gets two chances per vertex to find it instead of one.
#pragma once

#include <vector>

#include "core/math.h"
#include "render/shared/sky.h"
#include "scene/scene.h"

namespace multiray {

// The map's axes for up axis `up` (right-handed x, up, z): the middle column of the map
// (u = 1/2) looks along -z, u = 3/4 along +x, the seam u = 0 / 1 along +z. For y up
// these are the world axes (the convention of most HDR panoramas for y-up scenes).
struct EnvFrame {
  Vec3 x, up, z;
};
EnvFrame environment_frame(Vec3 up);

// Map texture coordinates (u right, v down, both in [0, 1]) of direction `d`, and back
// (render/shared/environment.h's equirect_uv and equirect_direction in this frame).
Vec2 direction_to_equirect(const EnvFrame& f, Vec3 d);
Vec3 equirect_to_direction(const EnvFrame& f, Vec2 uv);

// The probability with which next-event estimation samples the sun rather than the sky:
// in proportion to the irradiance each gives a surface facing it (luminance; the sky's is
// pi times its mean luminance), kept within [0.1, 0.9] so that neither is starved where
// the other is hidden; 1 without a sky. An even choice (what this replaced) spends half
// the light samples on a sky that gives, in default daylight (sky 0.3, sun 3), a quarter
// of the light: Sponza's variance per sample falls by a third with p = 0.76.
float sun_choice(float sun_irradiance, float sky_irradiance);

class EnvironmentLight {
 public:
  explicit EnvironmentLight(const Scene& scene);

  // Whether any light arrives from outside (next-event estimation is then used).
  bool on() const { return record_.on != 0; }
  // Radiance arriving along -`dir` from outside (dir points away from the scene).
  Vec3 radiance(Vec3 dir) const { return sky_radiance(&record_, map(), dir); }
  // Density with which sample(n, ...) returns `dir`.
  float pdf(Vec3 dir, Vec3 n) const { return sky_pdf(&record_, tables_.data(), dir, n); }
  EnvSample sample(Vec3 n, float u_choice, float u1, float u2) const {
    return sky_sample(&record_, tables_.data(), map(), n, u_choice, u1, u2);
  }
  // Luminance of the radiance averaged over all directions.
  float mean_luminance() const;

  // The light as the integrator reads it (render/shared/sky.h), for every backend: the
  // record (its `choice` left 0: RenderScene decides it), the map's sampling tables at the
  // record's offsets (empty without a map: per row the marginal CDF and probability, per
  // pixel the conditional CDF within its row and probability) and the map's radiance, 3
  // floats a pixel before map_scale (null without a map).
  const SkyRecord& record() const { return record_; }
  const std::vector<float>& tables() const { return tables_; }
  const float* map() const;
  // Luminance of the sun's irradiance at normal incidence (0 without a sun).
  float sun_irradiance() const;

 private:
  // Solid-angle mean of the sky's luminance (constant plus map), without the sun.
  float sky_mean_luminance() const;
  void build_map_tables();

  Vec3 constant_;
  const EnvironmentMap* map_ = nullptr;
  float map_scale_ = 1;
  Sun sun_;
  SkyRecord record_{};
  std::vector<float> tables_;
};

}  // namespace multiray
