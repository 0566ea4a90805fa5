#include "render/ambient_occlusion.h"

#include "render/path_tracer.h"
#include "render/rng.h"
#include "render/shared/sampling.h"

namespace multiray {

AmbientOcclusion::AmbientOcclusion(const RenderScene& rs) : rs_(rs) {
  const float extent = std::max(1e-6f, max_component(rs.scene.bounds().extent()));
  eps_ = 2e-5f * std::max(1.0f, extent);
  default_range_ = 0.3f * extent;
}

float AmbientOcclusion::occlusion(const Ray& primary, Rng& rng, const RenderSettings& settings,
                                  KernelStats& stats) const {
  Hit hit;
  ++stats.rays;
  if (!rs_.accel.intersect(primary, hit)) return 1.0f;
  const float range = settings.ao_distance > 0 ? settings.ao_distance : default_range_;
  const int rays = std::max(1, settings.ao_rays);
  Vec3 n = normalize(hit.ng);
  if (dot(n, primary.dir) > 0) n = -n;  // face the viewer
  const Vec3 p = primary.org + primary.dir * hit.t + n * eps_;
  const Frame frame = Frame::from_normal(n);
  int open = 0;
  for (int r = 0; r < rays; ++r) {
    const float u1 = rng.next(), u2 = rng.next();
    const Ray probe{p, frame.to_world(sample_cosine_hemisphere(u1, u2)), 0.0f, range};
    ++stats.rays;
    open += rs_.accel.occluded(probe) ? 0 : 1;
  }
  return float(open) / float(rays);
}

KernelStats AmbientOcclusion::render_rect(const ViewSetup& view, const RenderSettings& settings,
                                          Rect rect, Framebuffer& out) const {
  KernelStats stats;
  const PinholeCamera camera(view.camera, view.width, view.height);
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint32_t pixel = uint32_t(y) * uint32_t(view.width) + uint32_t(x);
      const int spp = view.samples_at(pixel, settings);
      float sum = 0;
      for (int s = 0; s < spp; ++s) {
        Rng rng = Rng::for_path(pixel, view.first_sample + uint32_t(s), view.seed_frame(),
                                view.view, settings.seed);
        const float jx = rng.next(), jy = rng.next();
        sum += occlusion(camera.ray(float(x) + jx, float(y) + jy), rng, settings, stats);
      }
      out.at(x, y) = Vec3(spp > 0 ? sum / float(spp) : 0.0f);
      stats.samples += uint64_t(spp);
    }
  return stats;
}

KernelStats AmbientOcclusion::render_samples(const ViewSetup& view, const RenderSettings& settings,
                                             const ImageSample* samples, size_t n,
                                             Vec3* value) const {
  KernelStats stats;
  const PinholeCamera camera(view.camera, view.width, view.height);
  for (size_t i = 0; i < n; ++i) {
    Rng rng = Rng::for_path(samples[i].key, 0, view.frame, view.view, settings.seed);
    value[i] = Vec3(occlusion(camera.ray(samples[i].x, samples[i].y), rng, settings, stats));
  }
  stats.samples += n;
  return stats;
}

}  // namespace multiray
