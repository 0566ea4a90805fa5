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
#include "scene/scene.h"

namespace multiray {

struct EnvSample {
  Vec3 dir;  // towards the light, unit
  Vec3 radiance;
  float pdf = 0;  // solid angle, with the choice between sun and sky
};

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
  bool on() const { return on_; }
  // Radiance arriving along -`dir` from outside (dir points away from the scene).
  Vec3 radiance(Vec3 dir) const;
  // Density with which sample(n, ...) returns `dir`.
  float pdf(Vec3 dir, Vec3 n) const;
  EnvSample sample(Vec3 n, float u_choice, float u1, float u2) const;
  // Luminance of the radiance averaged over all directions.
  float mean_luminance() const;

  // The map's sampling tables (empty without a map), for backends that sample it
  // themselves: per row the marginal CDF, per pixel the conditional CDF within its row.
  const std::vector<float>& row_cdf() const { return row_cdf_; }
  const std::vector<float>& column_cdf() const { return col_cdf_; }
  // The probabilities behind those CDFs: of each row, and of each pixel within its row.
  const std::vector<float>& row_pdf() const { return row_pdf_; }
  const std::vector<float>& pixel_pdf() const { return pix_pdf_; }
  // The rest of the sampling state, for the same backends: whether there is a sky
  // (constant or map), cosine of the sun's half angle, the sun cone's uniform solid-angle
  // density, and the probability with which sample() picks the sun.
  bool has_sky() const { return sky_; }
  float sun_cos() const { return sun_cos_; }
  float sun_pdf() const { return sun_pdf_; }
  float sun_probability() const { return p_sun_; }
  // Luminance of the sun's irradiance at normal incidence (0 without a sun).
  float sun_irradiance() const;

 private:
  // Solid-angle mean of the sky's luminance (constant plus map), without the sun.
  float sky_mean_luminance() const;
  float sky_pdf(Vec3 dir, Vec3 n) const;
  // Solid-angle density of the map distribution at `uv` (equirect_pdf).
  float map_pdf(Vec2 uv) const;
  Vec3 map_radiance(Vec2 uv) const;

  Vec3 constant_;
  const EnvironmentMap* map_ = nullptr;
  float map_scale_ = 1;
  EnvFrame frame_;
  Sun sun_;
  float sun_cos_ = 1, sun_pdf_ = 0;
  float p_sun_ = 0;  // probability of sampling the sun
  bool sky_ = false, on_ = false;
  std::vector<float> row_cdf_;  // height entries, last = 1
  std::vector<float> col_cdf_;  // width x height, each row's last = 1
  std::vector<float> row_pdf_;  // probability of each row
  std::vector<float> pix_pdf_;  // probability of each pixel within its row
};

}  // namespace multiray
