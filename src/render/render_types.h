// The plain types every CPU kernel shares: what to render (settings, view), the scene
// prepared for rendering, and what a kernel reports back.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/accel.h"
#include "render/compact_scene.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/shading_data.h"
#include "scene/scene.h"

namespace multiray {

struct FoveationFrame;
struct VolumeStyle;  // render/volume_raycaster.h

struct RenderSettings {
  int spp = 16;                 // samples per pixel (unless the view has a sample map)
  int max_bounces = 8;          // scattering events per path
  int rr_start = 3;             // first bounce at which Russian roulette may end a path
  uint64_t seed = 0;            // changes every random number (for variance tests)
  std::string kernel = "path";  // which kernel renders (render/kernel.h: cpu_kernels())
  int ao_rays = 2;              // occlusion rays per AO sample
  float ao_distance = 0.0f;     // occlusion range, scene units; 0: 0.3 of the scene size
  // Ray step relative to the user's, for kernels that march along rays (volumes); set by
  // the engine from Plan::quality for frame-time targeting. Surface kernels ignore it.
  float step_scale = 1.0f;
  // Next-event estimation of the environment (render/environment.h). Off, the sky is
  // reached by BSDF sampling alone, as before it was sampled: for variance comparisons.
  bool sample_environment = true;
  // The volume kernel's transfer function, block opacities and step (null for meshes);
  // shared, immutable, replaced when the transfer function changes.
  std::shared_ptr<const VolumeStyle> volume_style = {};
};

// One view of one frame: what the camera sees and the size of its image.
struct ViewSetup {
  Camera camera;
  int width = 0, height = 0;
  uint32_t view = 0;
  uint32_t frame = 0;
  // Adaptive edge sampling (Harada, GPU Pro 7 ch. 4, after Mitchell 1987): samples of each
  // pixel of this view, row-major; null means RenderSettings::spp everywhere. Must outlive
  // the frame.
  const std::vector<uint8_t>* spp_map = nullptr;
  // Foveated sampling (foveated.h): the frame's samples and neighbour lists; pixels are
  // reconstructed from samples instead of being sampled themselves. Null: not foveated.
  // Must outlive the frame.
  const FoveationFrame* foveation = nullptr;

  int samples_at(uint32_t pixel, const struct RenderSettings& s) const;
};

// One camera sample at a given image position (pixels, fractional, x right, y down) whose
// random numbers are keyed by (key, 0, frame, view, seed): the integrators' entry point for
// sample patterns that are not per-pixel (foveated sampling keys by pattern index).
struct ImageSample {
  float x = 0, y = 0;
  uint32_t key = 0;
};

struct KernelStats {
  uint64_t samples = 0;  // camera paths
  uint64_t rays = 0;     // closest-hit plus shadow rays (volumes: camera rays)
  uint64_t steps = 0;    // volume samples along rays (7 fetches each), volume kernel only
  KernelStats& operator+=(const KernelStats& o) {
    samples += o.samples, rays += o.rays, steps += o.steps;
    return *this;
  }
};

// Optional record of every ray traced, for the raw-Embree throughput benchmark.
struct RayLog {
  std::vector<Ray> closest, shadow;
};

// The scene as the CPU kernels need it: geometry, BVH and light sampler, built once.
// Two representations: full precision (Embree's BVH and a 64-byte shading record per
// triangle) or, given a compact scene, the quantized mesh and tree (compact_scene.h),
// decoded on access; lights, tangents and textures are full precision in both.
struct RenderScene {
  // `c`, when given, must outlive the RenderScene.
  explicit RenderScene(const Scene& s, const CompactScene* c = nullptr)
      : scene(s),
        compact(c),
        accel(s, compact),
        lights(s),
        environment(s),
        shading(compact ? std::vector<TriangleShading>() : build_shading_data(s)),
        tangents(build_tangents(s)),
        environment_choice_(choose_environment(s, lights, environment)) {}
  const Scene& scene;
  const CompactScene* compact;  // null at full precision
  Accel accel;
  LightSampler lights;
  EnvironmentLight environment;
  std::vector<TriangleShading> shading;   // empty with a compact scene: use shading_of()
  std::vector<TriangleTangent> tangents;  // empty without normal maps

  // The shading record of triangle `prim`: stored, or decoded from the compact mesh.
  TriangleShading shading_of(uint32_t prim) const {
    return compact ? decode_shading(*compact, prim) : shading[prim];
  }

  // Probability that next-event estimation samples the environment rather than an
  // emissive triangle: 0 or 1 when only one kind exists; with both, in proportion to an
  // estimate of the power each brings into the scene's bounding sphere, kept in
  // [0.1, 0.9] so that neither is starved when the estimate is poor.
  float environment_choice() const { return environment_choice_; }

  // Bytes this representation holds beyond the Scene: Embree's BVH (as Embree reports its
  // allocations) and the shading records, or the compact mesh and tree; tangents in both.
  uint64_t bytes() const {
    return (compact ? compact->bytes() : accel.bytes()) +
           shading.size() * sizeof(TriangleShading) + tangents.size() * sizeof(TriangleTangent);
  }

 private:
  static float choose_environment(const Scene& s, const LightSampler& lights,
                                  const EnvironmentLight& env);
  float environment_choice_;
};

inline int ViewSetup::samples_at(uint32_t pixel, const RenderSettings& s) const {
  return spp_map ? int((*spp_map)[pixel]) : s.spp;
}

}  // namespace multiray
