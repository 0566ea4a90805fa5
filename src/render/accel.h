// Ray queries against the scene, on Embree 3. One Accel is built per Scene and shared
// read-only by every CPU device and thread (Embree queries are thread-safe).
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "core/math.h"
#include "render/shared/ray.h"
#include "scene/scene.h"

namespace multiray {

// Materials with an alpha mode (scene.h AlphaMode) are cut out during traversal, for
// closest hits and shadow rays alike, by an Embree filter function: a point whose
// material passes_through() (render/surface.h) is not a hit. The random number of
// `blend` is a hash of the ray and the triangle, so a ray makes the same decision on
// every device, whatever the split.
//
// With a compact scene (compact_scene.h) the queries run the compact traversal
// (compact_accel.h) instead of Embree's, on quantized geometry.
struct CompactScene;
class Accel {
 public:
  // Builds a high-quality BVH over `scene` (which must outlive the Accel), or, given
  // `compact` (which must outlive it too), traverses that instead and builds nothing.
  explicit Accel(const Scene& scene, const CompactScene* compact = nullptr);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  // Closest hit along `ray` within [tmin, tmax]; false if none.
  bool intersect(const Ray& ray, Hit& hit) const;
  // True if anything lies along `ray` within [tmin, tmax].
  bool occluded(const Ray& ray) const;
  // occluded() of rays[0..n) into blocked[0..n), eight at a time through Embree's ray
  // packets (a wavefront's shadow rays start near one another and mostly share a
  // direction, the sun's, so a packet descends the tree together: 13% less time than one
  // ray at a time on Sponza's). A ray's answer is its own whatever its packet holds: an
  // occlusion query has no order among hits to depend on, so images stay independent of
  // how the frame was split (docs/design-notes.md, "Ray packets and the split").
  void occluded_batch(const Ray* rays, size_t n, uint8_t* blocked) const;
  // Bytes Embree holds for the BVH and its copy of the mesh (0 for a compact scene, whose
  // bytes are its own).
  uint64_t bytes() const { return uint64_t(std::max<int64_t>(0, embree_bytes_.load())); }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  const CompactScene* compact_ = nullptr;
  std::atomic<int64_t> embree_bytes_{0};  // Embree's builder allocates from many threads
  const Scene* cutouts_ = nullptr;        // the scene, when some material has an alpha mode
};

// The random number of a `blend` cut-out decision for `ray` at triangle `prim`, in [0, 1):
// a hash of the ray's origin and direction bits and the triangle (every traversal of the
// renderer uses it, so a ray decides alike on every device).
float cutout_hash(const Ray& ray, uint32_t prim);

// Sets flush-to-zero and denormals-are-zero on the calling thread, as Embree recommends
// for speed. Call once per rendering thread (cheap; idempotent).
void set_fast_float_mode();

}  // namespace multiray
