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

namespace {
void put3(float out[3], Vec3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }
}  // namespace

EnvironmentLight::EnvironmentLight(const Scene& scene)
    : constant_(scene.environment),
      map_(scene.environment_map.get()),
      map_scale_(scene.environment_map_scale),
      sun_(scene.sun) {
  if (map_ != nullptr && (map_->width <= 0 || map_->height <= 0)) map_ = nullptr;
  SkyRecord& k = record_;
  put3(k.constant_sky, constant_);
  const EnvFrame f = environment_frame(scene.up);
  put3(k.frame_x, f.x), put3(k.frame_up, f.up), put3(k.frame_z, f.z);
  k.sky_on = max_component(constant_) > 0 || map_ != nullptr ? 1u : 0u;
  k.sun_cos = 1.0f;
  if (sun_.on()) {
    k.sun_on = 1u;
    put3(k.sun_dir, sun_.direction);
    put3(k.sun_radiance, sun_.radiance);
    k.sun_cos = std::cos(sun_.half_angle_rad);
    k.sun_pdf = cone_pdf(k.sun_cos);
  }
  k.on = k.sky_on || k.sun_on ? 1u : 0u;
  k.p_sun = sun_.on() ? sun_choice(sun_irradiance(), kPi * sky_mean_luminance()) : 0.0f;
  k.map_scale = map_scale_;
  if (map_ != nullptr) build_map_tables();
}

// The map's sampling tables, weighted by luminance (map plus the constant sky) x
// sin(theta) of each pixel's centre: per row its marginal CDF and probability, per pixel
// its CDF and probability within the row.
void EnvironmentLight::build_map_tables() {
  const int w = map_->width, h = map_->height;
  SkyRecord& k = record_;
  k.map_width = w, k.map_height = h;
  const size_t pixels = size_t(w) * size_t(h);
  k.row_cdf = 0, k.row_pdf = uint32_t(h), k.col_cdf = uint32_t(2 * h);
  k.pix_pdf = uint32_t(2 * size_t(h) + pixels);
  tables_.assign(2 * size_t(h) + 2 * pixels, 0.0f);
  float* row_cdf = &tables_[k.row_cdf];
  float* row_pdf = &tables_[k.row_pdf];
  float* col_cdf = &tables_[k.col_cdf];
  float* pix_pdf = &tables_[k.pix_pdf];
  const float lum_constant = luminance(constant_);
  std::vector<double> row_sum(size_t(h), 0.0), weight(static_cast<size_t>(w));
  double total = 0;
  for (int y = 0; y < h; ++y) {
    const double st = std::sin(kPi * (y + 0.5) / h);
    double acc = 0;
    for (int x = 0; x < w; ++x) {
      const Vec3 c = map_->radiance[size_t(y) * size_t(w) + size_t(x)];
      weight[size_t(x)] = (double(luminance(c)) * map_scale_ + lum_constant) * st + 1e-12;
      acc += weight[size_t(x)];
    }
    double run = 0;
    for (int x = 0; x < w; ++x) {
      run += weight[size_t(x)];
      col_cdf[size_t(y) * size_t(w) + size_t(x)] = float(run / acc);
      pix_pdf[size_t(y) * size_t(w) + size_t(x)] = float(weight[size_t(x)] / acc);
    }
    col_cdf[size_t(y) * size_t(w) + size_t(w - 1)] = 1.0f;
    row_sum[size_t(y)] = acc;
    total += acc;
  }
  double run = 0;
  for (int y = 0; y < h; ++y) {
    run += row_sum[size_t(y)];
    row_cdf[y] = float(run / total);
    row_pdf[y] = float(row_sum[size_t(y)] / total);
  }
  row_cdf[h - 1] = 1.0f;
}

const float* EnvironmentLight::map() const {
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "the map's pixels are read as floats");
  return map_ ? &map_->radiance[0].x : nullptr;
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
  return luminance(sun_.radiance) * 2.0f * kPi *
         (1.0f - record_.sun_cos);  // radiance x solid angle
}

float EnvironmentLight::mean_luminance() const {
  // The sun's cone over the whole sphere: its irradiance / (4 pi).
  return sky_mean_luminance() + sun_irradiance() / (4.0f * kPi);
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
