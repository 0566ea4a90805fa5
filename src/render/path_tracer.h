// The CPU's path tracer: the integrator of render/shared/path.h (written once for every
// backend) driven in wavefronts of paths, with Embree tracing their rays and shadow rays
// in packets. It renders the samples of a rectangle of one view and knows nothing of
// devices or balancers; every path's random numbers come from (pixel, sample, frame,
// view), so the result is the same whoever renders which pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "render/kernel.h"
#include "render/render_types.h"
#include "render/scene_data.h"
#include "render/shared/camera.h"
#include "render/shared/texture.h"
#include "util/rect.h"

namespace multiray {

struct WavefrontPath;

class PathTracer : public Kernel {
 public:
  explicit PathTracer(const RenderScene& rs);

  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out) const override {
    return render_rect_logged(view, settings, rect, out, nullptr);
  }
  // render_rect(), recording every ray in `log` if given (must not be shared by threads).
  KernelStats render_rect_logged(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                                 Framebuffer& out, RayLog* log) const;

  // One path per sample; non-finite radiance becomes 0.
  KernelStats render_samples(const ViewSetup& view, const RenderSettings& settings,
                             const ImageSample* samples, size_t n, Vec3* radiance) const override;

 private:
  // Advances path `p` by one bounce given its closest hit (nullptr: it left the scene)
  // and, if known, the footprint of the hit's base colour texture.
  void step(struct WavefrontPath& p, const Hit* hit, const SceneData& sd,
            const RenderSettings& settings, const TexFootprint* base_footprint) const;
  // The shadow catcher's part (render/shadow_catcher.cpp): a hit on the plane replaces
  // `hit` when nearer; a bounce off the plane; one pixel's RGBA from its samples.
  void find_catcher(const struct CatcherPlane& plane, const Ray& ray, Hit& hit,
                    uint8_t& found) const;
  void catcher_step(struct WavefrontPath& p, const Hit& hit, const SceneData& sd,
                    const RenderSettings& settings) const;
  static void write_catcher_pixel(const struct WavefrontPath* samples, int spp,
                                  const RenderSettings& settings, Framebuffer& out, int x, int y);
  // Runs every path of `paths` to completion, a bounce at a time for all of them.
  void trace_batch(std::vector<struct WavefrontPath>& paths, const RenderSettings& settings,
                   KernelStats& stats, RayLog* log) const;

  const RenderScene& rs_;
  float eps_;  // ray-origin offset, scaled to the scene
};

// A Camera prepared for generating rays in an image of width x height pixels.
struct PinholeCamera {
  PinholeCamera(const Camera& cam, int width, int height);
  // Primary ray through image position (px, py) in pixels (fractional; y down):
  // render/shared/camera.h's camera_dir, as the OpenCL kernels compute it.
  Ray ray(float px, float py) const { return Ray{eye, camera_dir(&block_, px, py)}; }
  // The frame as the OpenCL parameter blocks carry it.
  const CameraBlock& block() const { return block_; }

  Vec3 eye, forward, right, up;
  float scale_x, scale_y;  // image-plane half extents at distance 1

 private:
  CameraBlock block_;
};

}  // namespace multiray
