// Unidirectional path tracer with next-event estimation, multiple importance sampling
// (power heuristic) and Russian roulette. It renders the samples of a rectangle of one
// view and knows nothing of devices or balancers; every path's random numbers come from
// (pixel, sample, frame, view), so the result is the same whoever renders which pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "render/kernel.h"
#include "render/render_types.h"
#include "render/shared/camera.h"
#include "util/rect.h"

namespace multiray {

class Bsdf;

struct PathState;

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
  // Advances path `p` by one bounce given its closest hit (nullptr: it left the scene) and,
  // if known, the footprint of the hit's base colour texture.
  void step(struct PathState& p, const Hit* hit, const RenderSettings& settings,
            const Texture::Footprint* base_footprint) const;
  // `p_env`: the probability that next-event estimation picks the environment (0: never).
  void escape(struct PathState& p, float p_env) const;
  // What escape() adds to the path's radiance.
  Vec3 escape_contribution(const struct PathState& p, float p_env) const;
  // A light sample and the path's continuation from a surface point with BSDF `bsdf`,
  // local `frame` and outgoing direction `wo`, at `pos` with geometric normal `ng`.
  void scatter(struct PathState& p, float p_env, const Bsdf& bsdf, const Frame& frame, Vec3 wo,
               Vec3 pos, Vec3 ng, const RenderSettings& settings) const;
  // The shadow catcher's part (render/shadow_catcher.cpp): a hit on the plane replaces
  // `hit` when nearer; a bounce off the plane; one pixel's RGBA from its samples.
  void find_catcher(const struct CatcherPlane& plane, const Ray& ray, Hit& hit,
                    uint8_t& found) const;
  void catcher_step(struct PathState& p, const Hit& hit, const RenderSettings& settings,
                    float p_env) const;
  static void write_catcher_pixel(const struct PathState* samples, int spp,
                                  const RenderSettings& settings, Framebuffer& out, int x, int y);
  void sample_light(struct PathState& p, float p_env, const Bsdf& bsdf, const Frame& frame,
                    Vec3 wo, Vec3 pos, Vec3 ng) const;
  // Runs every path of `paths` to completion, a bounce at a time for all of them.
  void trace_batch(std::vector<struct PathState>& paths, const RenderSettings& settings,
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
