// What a render request says, as plain data: the settings, one view of a frame, a sample
// at an arbitrary image position, and what a kernel reports back. Free of Embree, OpenCL
// and the prepared scene on purpose: device/device.h (the Device interface, which every
// layer above sees) includes this header and nothing heavier from render/
// (tests/render/device_header_test.cpp checks it). The scene prepared for rendering is
// render_types.h.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.h"  // Camera (plain data; scene.h includes only core/math.h)

namespace multiray {

struct FoveationFrame;
struct VolumeStyle;  // render/volume_raycaster.h

struct RenderSettings {
  int spp = 16;         // samples per pixel (unless the view has a sample map)
  int max_bounces = 8;  // scattering events per path
  // First bounce at which Russian roulette may end a path (with rr_survival's square root:
  // from the second, time x variance on Sponza is the third's within 1-2% for 20% less time
  // a sample; from the first it is 28% worse; docs/benchmarks.md "Equal noise against Cycles").
  int rr_start = 2;
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
  // --clamp: the largest RGB component one camera sample's radiance may reach before it is
  // averaged into its pixel (render/shared/sampling.h: clamp_sample); 0: no limit. Path
  // kernels only (path, direct; CPU and OpenCL).
  float sample_clamp = 0.0f;
  // The shadow catcher of augmented reality (render/shadow_catcher.h), --ground: the plane
  // where coordinate catcher_axis (0, 1, 2 = x, y, z; -1: no catcher) equals
  // catcher_height, diffuse with albedo catcher_albedo, standing for the real ground under
  // the virtual objects. With it the path kernel writes the objects' premultiplied radiance
  // and Framebuffer::alpha instead of the whole scene's radiance. CPU path kernel only.
  int catcher_axis = -1;
  float catcher_height = 0.0f;
  float catcher_albedo = 0.5f;
  // Feature buffers (AOVs: albedo, normal, depth, variance, emission; render/shared/aov.h),
  // recorded beside the beauty into Framebuffer::features, all five together. Path kernel only
  // (CPU and OpenCL), rectangles only (not foveated point samples). Off: no buffer, no store, and
  // the beauty is the same to the bit.
  bool feature_buffers = false;
  // The volume kernel's transfer function, block opacities and step (null for meshes);
  // shared, immutable, replaced when the transfer function changes.
  std::shared_ptr<const VolumeStyle> volume_style = {};
};

// The settings another rank needs, in wire order, each given to `f` as (name, field): the
// MPI codec (distributed/protocol.cpp) writes and reads exactly these. A new field of
// RenderSettings goes here, or into kRankLocalSettings when every rank makes its own; the
// codec counts RenderSettings' fields at compile time and does not build while one is in
// neither list.
template <class Settings, class F>
void for_each_sent_setting(Settings& s, F&& f) {
  f("spp", s.spp), f("max_bounces", s.max_bounces), f("rr_start", s.rr_start);
  f("seed", s.seed), f("kernel", s.kernel), f("ao_rays", s.ao_rays);
  f("ao_distance", s.ao_distance), f("step_scale", s.step_scale);
  f("sample_environment", s.sample_environment), f("sample_clamp", s.sample_clamp);
  f("catcher_axis", s.catcher_axis), f("catcher_height", s.catcher_height);
  f("catcher_albedo", s.catcher_albedo), f("feature_buffers", s.feature_buffers);
}
inline constexpr size_t kSentSettings = 14;
// Built by each rank from its own data: the volume style (from the transfer function).
inline constexpr const char* kRankLocalSettings[] = {"volume_style"};

// One view of one frame: what the camera sees and the size of its image.
struct ViewSetup {
  Camera camera;
  int width = 0, height = 0;
  uint32_t view = 0;
  uint32_t frame = 0;
  // Progressive sampling (engine/session.h, set_progressive: the viewer's refinement): a
  // frame whose camera and settings are those of the frames before it continues their
  // sample sequence instead of starting its own, so that the frames' mean converges as one
  // render of all their samples would (render/shared/sobol.h: the first 2^m samples of a
  // pixel are spread evenly, the next 2^m too, and together they are again). Sample s of
  // a pixel in this frame is sample first_sample + s of the sequence frame `sample_frame`
  // began. first_sample 0: the frame begins its own (sample_frame unused).
  uint32_t first_sample = 0;
  uint32_t sample_frame = 0;
  // The frame whose sequence this frame's samples belong to: what seeds them.
  uint32_t seed_frame() const { return first_sample > 0 ? sample_frame : frame; }
  // Adaptive edge sampling (Harada, GPU Pro 7 ch. 4, after Mitchell 1987): samples of each
  // pixel of this view, row-major; null means RenderSettings::spp everywhere. Must outlive
  // the frame.
  const std::vector<uint8_t>* spp_map = nullptr;
  // Foveated sampling (foveated.h): the frame's samples and neighbour lists; pixels are
  // reconstructed from samples instead of being sampled themselves. Null: not foveated.
  // Must outlive the frame.
  const FoveationFrame* foveation = nullptr;

  int samples_at(uint32_t pixel, const RenderSettings& s) const {
    return spp_map ? int((*spp_map)[pixel]) : s.spp;
  }
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

}  // namespace multiray
