#include "render/depth_kernel.h"

#include "render/path_tracer.h"

namespace multiray {

namespace {
float depth_along(const RenderScene& rs, const Ray& ray) {
  Hit hit;
  return rs.accel.intersect(ray, hit) ? hit.t : 0.0f;
}
}  // namespace

KernelStats DepthKernel::render_rect(const ViewSetup& view, const RenderSettings&, Rect rect,
                                     Framebuffer& out) const {
  const PinholeCamera camera(view.camera, view.width, view.height);
  KernelStats stats;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      out.at(x, y) = Vec3(depth_along(rs_, camera.ray(float(x) + 0.5f, float(y) + 0.5f)));
      ++stats.samples, ++stats.rays;
    }
  return stats;
}

KernelStats DepthKernel::render_samples(const ViewSetup& view, const RenderSettings&,
                                        const ImageSample* samples, size_t n, Vec3* values) const {
  const PinholeCamera camera(view.camera, view.width, view.height);
  for (size_t i = 0; i < n; ++i)
    values[i] = Vec3(depth_along(rs_, camera.ray(samples[i].x, samples[i].y)));
  return KernelStats{n, n};
}

}  // namespace multiray
