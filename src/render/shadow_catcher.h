// The shadow catcher of augmented reality: the differential rendering of Debevec,
// "Rendering Synthetic Objects into Real Scenes" (SIGGRAPH 98, pp. 189-198) inside the path
// tracer, for the proof of concept of ray-traced objects over a device's camera image in
// Seo, Park & Ihm, "Efficient Ray Tracing of Large 3D Scenes for Mobile Distributed
// Computing Environments" (Sensors 22(2), 2022), §5.3.
//
// The real ground is stood for by a diffuse plane (RenderSettings::catcher_*, --ground).
// Each camera sample is of one of three kinds, by what its camera ray meets first:
// - background: nothing; the real image shows through unchanged;
// - object: a virtual object; its radiance (lit by the environment, by the catcher and by
//   the other objects) covers the real image;
// - catcher: the plane. The sample estimates the plane's radiance twice with the same
//   random numbers: with the objects (its light sample's shadow ray tested, its path
//   continued through the scene) and without them (the light sample always arrives, and the
//   continued path's first segment escapes to the environment). Where no object is in the
//   way the two are the same number, bit for bit.
// A pixel's real image is scaled by r = lum(sum with) / lum(sum without) over its catcher
// samples, clamped to [0, 1]: the catcher darkens (shadows) and never brightens (light the
// objects reflect onto the ground is dropped). The kernel's output is an RGBA layer with
// premultiplied colour,
//   rgb   = (sum of the object samples' radiance) / spp
//   alpha = (object samples + catcher samples x (1 - r)) / spp,
// whose composite over a real image B is rgb + (1 - alpha) B (core/composite.h).
#pragma once

#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "render/accel.h"
#include "render/render_settings.h"

namespace multiray {

// Hit::prim of a hit on the catcher (no triangle has this index).
inline constexpr uint32_t kCatcherPrim = 0xffffffffu;

// The plane {p[axis] = height}, two-sided.
struct CatcherPlane {
  explicit CatcherPlane(const RenderSettings& s)
      : axis(s.catcher_axis), height(s.catcher_height), albedo(s.catcher_albedo) {}
  bool on() const { return axis >= 0; }
  // Distance along `ray` to the plane when it lies in (ray.tmin, tmax), else INFINITY.
  float intersect(const Ray& ray, float tmax) const {
    const float d = ray.dir[axis];
    if (d == 0.0f) return INFINITY;
    const float t = (height - ray.org[axis]) / d;
    return t > ray.tmin && t < tmax ? t : INFINITY;
  }
  // The unit normal on the side of point `from`.
  Vec3 normal_facing(Vec3 from) const {
    Vec3 n(0.0f);
    n[axis] = from[axis] >= height ? 1.0f : -1.0f;
    return n;
  }

  int axis;
  float height, albedo;
};

enum class SampleKind : uint8_t { background, object, catcher };

// One pixel's camera samples, summed as they finish.
struct CatcherPixel {
  Vec3 objects{0.0f};              // radiance of the object samples
  Vec3 with{0.0f}, without{0.0f};  // the catcher samples' two estimates
  int object_samples = 0, catcher_samples = 0;

  void add(SampleKind kind, Vec3 L, Vec3 L_without);
  // The ratio r of the pixel's catcher samples: 1 when they carry no light without the
  // objects (or there are none).
  float shadow_ratio() const;
  // The RGBA layer's pixel for `spp` samples (premultiplied rgb).
  void resolve(int spp, Vec3& rgb, float& alpha) const;
};

}  // namespace multiray
