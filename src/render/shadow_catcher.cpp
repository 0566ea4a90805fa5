#include "render/shadow_catcher.h"

#include <algorithm>

#include "render/bsdf.h"
#include "render/path_state.h"
#include "render/path_tracer.h"
#include "render/shared/sampling.h"

namespace multiray {

void CatcherPixel::add(SampleKind kind, Vec3 L, Vec3 L_without) {
  if (kind == SampleKind::object) {
    objects += L;
    ++object_samples;
  } else if (kind == SampleKind::catcher) {
    with += L;
    without += L_without;
    ++catcher_samples;
  }
}

float CatcherPixel::shadow_ratio() const {
  const float base = luminance(without);
  if (!(base > 0.0f)) return 1.0f;
  return std::clamp(luminance(with) / base, 0.0f, 1.0f);
}

void CatcherPixel::resolve(int spp, Vec3& rgb, float& alpha) const {
  if (spp <= 0) {
    rgb = Vec3(0.0f), alpha = 0.0f;
    return;
  }
  const float inv = 1.0f / float(spp);
  rgb = objects * inv;
  const float covered = float(object_samples) + float(catcher_samples) * (1.0f - shadow_ratio());
  alpha = std::clamp(covered * inv, 0.0f, 1.0f);
}

// A bounce off the catcher: a Lambertian plane of the catcher's albedo, shaded like any
// surface. On the camera ray's hit (depth 0) the same vertex is also estimated without the
// objects, from the light sample and continuation scatter() just drew.
void PathTracer::catcher_step(WavefrontPath& p, const Hit& hit, const SceneData& sd,
                              const RenderSettings& settings) const {
  const CatcherPlane plane(settings);
  const bool camera_hit = p.depth == 0;
  if (camera_hit) p.kind = SampleKind::catcher;
  if (p.depth >= settings.max_bounces) {
    p.alive = false;
    return;
  }
  const Vec3 pos = p.ray.org + p.ray.dir * hit.t;
  const Vec3 n = plane.normal_facing(p.ray.org);
  const Material plain;  // only its ior and transmission are read
  const BsdfParams bsdf = bsdf_params(Vec3(plane.albedo), 0.0f, 1.0f, material_ior(plain),
                                      material_is_dielectric(plain));
  const Frame frame = Frame::from_normal(n);
  path_scatter(&sd, &p, &bsdf, &frame, frame.to_local(-p.ray.dir), pos, n,
               PathSettings{settings.max_bounces, settings.rr_start});
  if (!camera_hit) return;
  // Summed in the order the path adds the same terms to L (light sample, then escape), so
  // an unobstructed sample gives L == L_without exactly.
  Vec3 without(0.0f);
  if (p.has_shadow) without += p.shadow_contribution;
  if (p.alive) without += path_escape_contribution(&sd, &p);
  p.L_without = without;
}

void PathTracer::find_catcher(const CatcherPlane& plane, const Ray& ray, Hit& hit,
                              uint8_t& found) const {
  const float t = plane.intersect(ray, found ? hit.t : ray.tmax);
  if (t == INFINITY) return;
  hit = Hit{};
  hit.t = t, hit.prim = kCatcherPrim;
  found = 1;
}

void PathTracer::write_catcher_pixel(const WavefrontPath* samples, int spp,
                                     const RenderSettings& settings, Framebuffer& out, int x,
                                     int y) {
  CatcherPixel px;
  for (int s = 0; s < spp; ++s) {
    const WavefrontPath& p = samples[s];
    const auto clean = [&](Vec3 L) {
      return clamp_sample(is_finite(L) ? L : Vec3(0.0f), settings.sample_clamp);
    };
    px.add(p.kind, clean(p.L), clean(p.L_without));
  }
  float alpha = 0;
  px.resolve(spp, out.at(x, y), alpha);
  if (!out.alpha.empty()) out.alpha[size_t(y) * size_t(out.width) + size_t(x)] = alpha;
}

}  // namespace multiray
