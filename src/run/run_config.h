// What a run is asked to do, as plain data: the scene, the image, the devices, sampling,
// lighting, volumes and the distributed layout. The command line fills one (app/), as do
// the bench programs and the fuzz targets; build_run() (run/run.h) checks every value
// strictly and builds from it. Values are kept as the user wrote them where their grammar
// is richer than a number (resolution, seed, camera, ...): build_run parses them, so every
// caller gets the same one-line errors.
#pragma once

#include <string>
#include <vector>

#include "distributed/options.h"
#include "render/foveated_pattern.h"

namespace multiray {

// --tf, --step, --raw and the frame-time targeting of volumes.
struct VolumeOptions {
  std::string tf = "auto";     // a preset name or a JSON file; auto: by voxel type
  float step = 0.5f;           // ray step, in voxel lengths
  std::string raw;             // "NXxNYxNZ:TYPE[...]" for a headerless .raw file
  double target_ms = 0;        // frame-time target; 0: none
  std::string adapt = "auto";  // none | last-frame | predict[:q=Q] | two-pass, a list for bench
  std::string adapt_space = "auto";  // auto | ray | image | hybrid (balance/targeting.h)
  int prepass_stride = 4;            // pixels per pre-pass ray each way; 0: no prediction
  std::string cost_model = "paper";  // paper | ours [:tf=0|1] (engine/cost_model.h)
  // bench: render each frame at this step (voxel lengths) as the image-error reference
  // of the adaptation lanes (Bruder et al.'s Table 4: 0.1); 0: lane 0's full quality.
  float reference_step = 0;
  std::string sequence;  // interaction sequence file (sequence.h)
};

// Everything render, bench and view share.
struct RunConfig {
  std::string scene_path;  // empty: built-in Cornell box
  std::string resolution = "640x360";
  int spp = 0;        // 0: mesh_spp for meshes, 1 for volumes
  int mesh_spp = 16;  // what --spp 0 means for meshes (bench: 4)
  int bounces = 8;
  // --clamp: the largest RGB component one camera sample may contribute (path kernels);
  // 0: no limit. RenderSettings::sample_clamp.
  float clamp = 0.0f;
  int frames = 1;
  std::string camera;                 // "ex,ey,ez,tx,ty,tz,ux,uy,uz,fov" or empty
  std::string up = "auto";            // [+-]x|y|z; auto: y for meshes, z for volumes
  std::string camera_path = "fixed";  // fixed | orbit | orbit:PERIOD | FILE.json
  // Augmented reality (run/ar_setup.h): the shadow catcher, "AXIS=HEIGHT[,albedo=A]" or
  // empty (none); the capture's camera poses (scene/ar_poses.h), a file or empty.
  std::string ground;
  std::string poses;
  std::string devices = "auto";      // run/catalog.h auto_devices; threads=0: all hardware threads
  std::string seed = "0";            // a whole number in [0, 2^64); parsed strictly in build_run
  std::string env = "auto";          // auto | V | R,G,B | FILE.hdr|.exr (run/lighting.h)
  double env_scale = 1.0;            // multiplies an environment map
  std::string sun = "auto";          // auto | off | AZ,EL[,IRRADIANCE[,DIAMETER]]
  std::vector<std::string> perturb;  // FRAME:DEVICE:SPEED
  std::string views = "1x1";         // KxL light-field grid
  // Between grid views: "auto" (kViewSpacingOfDistance of the camera's distance to its
  // target, run.cpp) or a distance in scene units.
  std::string view_spacing = "auto";
  float stereo = 0.0f;     // > 0: a stereo pair this far apart (overrides views)
  std::string mapping;     // strips | views | empty (the balancer's own layout)
  std::string integrator;  // a CPU kernel's name (render/kernel.h); empty: by scene
  VolumeOptions volume;    // --tf, --step, --raw
  int ao_rays = 2;
  float ao_distance = 0.0f;          // 0: 0.3 of the scene size
  std::string sampling = "uniform";  // uniform | adaptive | foveated
  int edge_spp = 5;                  // adaptive: samples of edge pixels (others get 1)
  int reference_spacing = 0;         // reproject: references every K views; 0: the centre
  std::string gaze = "0.5,0.5";      // foveated: gaze point X,Y, normalised, (0,0) top left
  std::string gaze_path = "fixed";   // foveated: fixed | orbit | orbit:PERIOD
  FoveationParams foveation;         // foveated: --fovea-spp, --fovea-radius, --periphery-spp
  bool allow_outside_paths = false;  // files a scene names may lie outside its folder
  std::string max_memory = "auto";   // bytes (K/M/G suffixes) or auto: half of physical RAM
  // Bytes the command keeps in memory per frame, for the estimate (bench: every lane's
  // records; render keeps none: its records go to disk as frames finish).
  double kept_bytes_per_frame = 0;
  DistributedOptions distributed;  // --distributed and its options (distributed/cluster.h)
  // --aov: the feature buffers to record (core/feature_buffers.h aov_names(), checked by
  // check_aov_names); empty: none. Any name records all five (RenderSettings::
  // feature_buffers); the list says which the outputs keep.
  std::vector<std::string> aovs;
  // --denoise: none | atrous | svgf | auto (render/denoise.h denoise_methods()); auto
  // resolves with `png_output` and `viewer` (resolve_denoise) and means none where the
  // run cannot record feature buffers. Commands set the two flags for what they write.
  std::string denoise = "none";
  // --denoise-normal: turn | svgf (render/denoise.h denoise_normal_terms()).
  std::string denoise_normal = "turn";
  // --svgf-history: filtered (the paper's) | accumulated (ours until 2026-12-04);
  // DenoiseParams::history_filtered.
  std::string svgf_history = "filtered";
  bool png_output = false;  // the run writes PNG images (render without --exr only, ...)
  bool viewer = false;      // the live viewer
};

}  // namespace multiray
