#include "render/environment.h"

#include <algorithm>
#include <cmath>

#include "render/render_types.h"
#include "render/shared/environment.h"
#include "render/shared/sampling.h"

namespace multiray {

EnvFrame environment_frame(Vec3 up) {
  // A world axis across `up`, then the third by the right-hand rule.
  const Vec3 across = std::abs(up.x) < 0.5f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 x = normalize(across - up * dot(across, up));
  return EnvFrame{x, up, cross(x, up)};
}

Vec2 direction_to_equirect(const EnvFrame& f, Vec3 d) { return equirect_uv(f.x, f.up, f.z, d); }

Vec3 equirect_to_direction(const EnvFrame& f, Vec2 uv) {
  return equirect_direction(f.x, f.up, f.z, uv);
}

EnvironmentLight::EnvironmentLight(const Scene& scene)
    : constant_(scene.environment),
      map_(scene.environment_map.get()),
      map_scale_(scene.environment_map_scale),
      frame_(environment_frame(scene.up)),
      sun_(scene.sun) {
  if (map_ != nullptr && (map_->width <= 0 || map_->height <= 0)) map_ = nullptr;
  sky_ = max_component(constant_) > 0 || map_ != nullptr;
  if (sun_.on()) {
    sun_cos_ = std::cos(sun_.half_angle_rad);
    sun_pdf_ = cone_pdf(sun_cos_);
  }
  on_ = sky_ || sun_.on();
  p_sun_ = sun_.on() ? sun_choice(sun_irradiance(), kPi * sky_mean_luminance()) : 0.0f;
  if (map_ == nullptr) return;
  // Weights: luminance (map plus the constant sky) x sin(theta) of each pixel's centre.
  const int w = map_->width, h = map_->height;
  const float lum_constant = luminance(constant_);
  std::vector<double> row_sum(size_t(h), 0.0);
  col_cdf_.resize(size_t(w) * size_t(h));
  pix_pdf_.resize(col_cdf_.size());
  double total = 0;
  for (int y = 0; y < h; ++y) {
    const double st = std::sin(kPi * (y + 0.5) / h);
    double acc = 0;
    std::vector<double> weight(static_cast<size_t>(w));
    for (int x = 0; x < w; ++x) {
      const Vec3 c = map_->radiance[size_t(y) * size_t(w) + size_t(x)];
      weight[size_t(x)] = (double(luminance(c)) * map_scale_ + lum_constant) * st + 1e-12;
      acc += weight[size_t(x)];
    }
    double run = 0;
    for (int x = 0; x < w; ++x) {
      run += weight[size_t(x)];
      col_cdf_[size_t(y) * size_t(w) + size_t(x)] = float(run / acc);
      pix_pdf_[size_t(y) * size_t(w) + size_t(x)] = float(weight[size_t(x)] / acc);
    }
    col_cdf_[size_t(y) * size_t(w) + size_t(w - 1)] = 1.0f;
    row_sum[size_t(y)] = acc;
    total += acc;
  }
  double run = 0;
  for (int y = 0; y < h; ++y) {
    run += row_sum[size_t(y)];
    row_cdf_.push_back(float(run / total));
    row_pdf_.push_back(float(row_sum[size_t(y)] / total));
  }
  row_cdf_.back() = 1.0f;
}

float sun_choice(float sun_irradiance, float sky_irradiance) {
  if (!(sky_irradiance > 0)) return 1.0f;
  return std::clamp(sun_irradiance / (sun_irradiance + sky_irradiance), 0.1f, 0.9f);
}

float EnvironmentLight::sky_mean_luminance() const {
  double lum = luminance(constant_);
  if (map_ != nullptr) {
    // Pixels weighted by the solid angle of their row.
    double sum = 0, weight = 0;
    for (int y = 0; y < map_->height; ++y) {
      const double st = std::sin(kPi * (y + 0.5) / map_->height);
      for (int x = 0; x < map_->width; ++x)
        sum += st * luminance(map_->radiance[size_t(y) * size_t(map_->width) + size_t(x)]);
      weight += st * map_->width;
    }
    lum += map_scale_ * sum / weight;
  }
  return float(lum);
}

float EnvironmentLight::sun_irradiance() const {
  if (!sun_.on()) return 0.0f;
  return luminance(sun_.radiance) * 2.0f * kPi * (1.0f - sun_cos_);  // radiance x solid angle
}

float EnvironmentLight::mean_luminance() const {
  // The sun's cone over the whole sphere: its irradiance / (4 pi).
  return sky_mean_luminance() + sun_irradiance() / (4.0f * kPi);
}

Vec3 EnvironmentLight::map_radiance(Vec2 uv) const {
  const int x = equirect_texel(uv.x, map_->width), y = equirect_texel(uv.y, map_->height);
  return map_->radiance[size_t(y) * size_t(map_->width) + size_t(x)] * map_scale_;
}

Vec3 EnvironmentLight::radiance(Vec3 dir) const {
  Vec3 L = constant_;
  if (map_ != nullptr) L += map_radiance(direction_to_equirect(frame_, dir));
  if (sun_.on() && dot(dir, sun_.direction) >= sun_cos_) L += sun_.radiance;
  return L;
}

float EnvironmentLight::map_pdf(Vec2 uv) const {
  const int x = equirect_texel(uv.x, map_->width), y = equirect_texel(uv.y, map_->height);
  return equirect_pdf(row_pdf_[size_t(y)], pix_pdf_[size_t(y) * size_t(map_->width) + size_t(x)],
                      map_->width, map_->height, uv.y);
}

float EnvironmentLight::sky_pdf(Vec3 dir, Vec3 n) const {
  if (!sky_) return 0;
  if (map_ != nullptr) return map_pdf(direction_to_equirect(frame_, dir));
  return std::max(dot(dir, n), 0.0f) * kInvPi;
}

float EnvironmentLight::pdf(Vec3 dir, Vec3 n) const {
  float p = (1.0f - p_sun_) * sky_pdf(dir, n);
  if (sun_.on() && dot(dir, sun_.direction) >= sun_cos_) p += p_sun_ * sun_pdf_;
  return p;
}

EnvSample EnvironmentLight::sample(Vec3 n, float u_choice, float u1, float u2) const {
  EnvSample s;
  if (u_choice < p_sun_) {
    // Uniform in the cone around the sun's direction.
    const Frame f = Frame::from_normal(sun_.direction);
    s.dir = normalize(f.to_world(sample_cone(sun_cos_, u1, u2)));
  } else if (map_ != nullptr) {
    s.dir = equirect_to_direction(
        frame_, sample_equirect(row_cdf_.data(), col_cdf_.data(), uint32_t(map_->width),
                                uint32_t(map_->height), u1, u2));
  } else {
    const Frame f = Frame::from_normal(n);
    s.dir = f.to_world(sample_cosine_hemisphere(u1, u2));
  }
  s.pdf = pdf(s.dir, n);
  s.radiance = radiance(s.dir);
  return s;
}

float RenderScene::choose_environment(const Scene& s, const LightSampler& lights,
                                      const EnvironmentLight& env) {
  if (!env.on()) return 0.0f;
  if (lights.empty()) return 1.0f;
  // Power / pi through the bounding sphere: mean radiance x its cross-section x 4 (the
  // sphere's area over pi r^2) for the environment, area x radiance for the lights.
  const float r = 0.5f * length(s.bounds().extent());
  const double env_power = double(env.mean_luminance()) * 4.0 * kPi * double(r) * double(r);
  const double share = env_power / (env_power + lights.total_power());
  return float(std::clamp(share, 0.1, 0.9));
}

}  // namespace multiray
