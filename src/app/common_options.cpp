// The options render, bench and view share, declared on a CLI11 command and stored into a
// RunConfig (run/run_config.h), which run/ then checks and builds from.
#include <string>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "render/denoise.h"
#include "run/catalog.h"

namespace multiray::app {

namespace {

std::string preset_list() {
  std::string names;
  for (const std::string& n : transfer_presets()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

void add_volume_options(CLI::App& cmd, VolumeOptions& o) {
  cmd.add_option("--tf", o.tf,
                 "Volumes: transfer function, a preset (" + preset_list() +
                     ") or a JSON file (docs/volumes.md); auto: ct-bone for 16-bit data, angio "
                     "for 8-bit")
      ->capture_default_str();
  cmd.add_option("--step", o.step,
                 "Volumes: ray step in voxel lengths (the shortest spacing), in [0.01, 64]")
      ->capture_default_str();
  cmd.add_option("--target-ms", o.target_ms,
                 "Volumes: frame-time target in ms for --adapt (0: none)")
      ->capture_default_str();
  cmd.add_option(
         "--adapt", o.adapt,
         "Volumes: frame-time targeting: none, last-frame (scale quality by the last "
         "frame's time), predict (Bruder et al.: choose quality from the predicted "
         "time; predict:q=Q scales predictions by the Q-quantile of recent measured/predicted "
         "ratios, e.g. q=0.9), two-pass (a pass at a quarter of the last frame's quality, "
         "then a second pass filling the budget if the first took under half of it; "
         "two-pass:probe=fixed: the first pass at a quarter of full quality); auto: predict with "
         "--target-ms, "
         "else none. bench takes a list and runs "
         "every balancer once per mode")
      ->capture_default_str();
  cmd.add_option("--adapt-space", o.adapt_space,
                 "Volumes: what --adapt changes: auto (the resolution down to half per side, "
                 "then the step up to x2, no further), ray (the step), image (the resolution, "
                 "upsampled) or hybrid (both); ray, image and hybrid go down to 1/64 of the work")
      ->capture_default_str();
  cmd.add_option("--cost-model", o.cost_model,
                 "Volumes: the KRLS cost model: paper (Bruder et al. 5.1: gamma 0.00025, "
                 "tolerance 0.006, up to 10M support vectors, the features as measured, the "
                 "cost per sample itself learnt) or ours (gamma 0.5, tolerance 0.001, at most "
                 "200 support vectors, features scaled to a unit, log cost learnt, and the "
                 "transfer function's feature); :tf=1 adds that feature, :tf=0 leaves it out")
      ->capture_default_str();
  cmd.add_option("--prepass-stride", o.prepass_stride,
                 "Volumes: one prediction pre-pass ray per NxN pixels (0: no prediction; "
                 "balancers then split by area)")
      ->capture_default_str();
  cmd.add_option("--sequence", o.sequence,
                 "Volumes: interaction sequence JSON (orbit, zoom, transfer-function switches "
                 "at given frames; docs/volumes.md); replaces --camera-path");
  cmd.add_option("--raw", o.raw,
                 "Volumes: read the scene file as headerless voxels "
                 "NXxNYxNZ:TYPE[:be|:le][:spacing=SX,SY,SZ], TYPE uint8, int8, uint16 or int16");
}

void add_distributed_options(CLI::App& cmd, DistributedOptions& o) {
  cmd.add_flag("--distributed", o.enabled,
               "Run as one MPI job (mpirun -np K multiray ... --distributed): rank 0 plans, "
               "composites and writes; every other rank is a worker that loads the same scene "
               "path and renders what it is sent over its own --devices (docs/distributed.md)");
  cmd.add_option("--rank-devices", o.rank_devices,
                 "R=DEVICES, repeatable: rank R's --devices (e.g. 2=cpu:threads=1:speed=0.5)");
  cmd.add_flag("--master-renders", o.master_renders,
               "Rank 0 renders too, with its own --devices (default: it only plans and "
               "composites)");
  cmd.add_option("--rank-balancer", o.rank_balancer,
                 "How each worker splits what it is sent across its local devices (any "
                 "--balancer; Harada's hierarchy: the master cuts row bands, each worker cuts its "
                 "band into columns)")
      ->capture_default_str();
  cmd.add_flag("--rank-same-direction", o.same_direction,
               "Workers split along the master's axis instead of the other one");
  cmd.add_option("--link", o.link,
                 "Emulated network between master and workers (always labelled emulated): "
                 "none, lan (0.1 ms, 10 Gbit/s), wifi (5 ms, 200 Mbit/s, a mobile cluster), "
                 "or LATENCY_MS,MBIT[,separate]; the master's link is shared by all workers "
                 "unless 'separate'")
      ->capture_default_str();
  cmd.add_option("--scene-from", o.scene_from,
                 "Where workers get the scene: shared (each loads the same path: a shared "
                 "folder or a copy on every machine) or master (the master sends the scene it "
                 "loaded, lighting included; up to 2 GiB)")
      ->capture_default_str();
  if (!zstd_results_available()) o.result_encoding = "float";  // built without zstd
  cmd.add_option("--result-encoding", o.result_encoding,
                 "How workers send pixels to the master: float (12 bytes a pixel, exact), "
                 "float+zstd (the same floats compressed with zstd: exact, fewer bytes), half "
                 "(16-bit half floats, 6 bytes: LOSSY, about 3 significant digits, values "
                 "beyond 65504 clamp to it) or half+zstd (half, compressed); zstd needs a "
                 "build with libzstd-dev (docs/distributed.md). The denoiser's feature "
                 "buffers travel the same way: 44 more bytes a pixel as float")
      ->capture_default_str();
  cmd.add_option("--worker-timeout", o.worker_timeout_s,
                 "Seconds of silence (no result, no part of one, no heartbeat) after which a "
                 "worker is given up on and its work re-assigned. Results cross in parts of "
                 "128 KiB, two at a time: a worker's link must carry 256 KiB within it")
      ->capture_default_str();
  cmd.add_option("--depth", o.depth,
                 "Items pulled on demand that a worker holds at once: N in 1..64 (2: it renders "
                 "one while the previous one's pixels travel, as Seo et al.), or auto: from 2, "
                 "deeper while the worker measured itself waiting for items")
      ->capture_default_str();
}
}  // namespace

void add_common_options(CLI::App& cmd, RunConfig& o) {
  cmd.add_option("scene", o.scene_path,
                 "Scene file (.gltf, .glb, .obj, .ply; .fbx, .dae, .3ds, .stl, .off, .blend and "
                 "more through assimp, see docs/scene-formats.md) or volume (.nhdr, .nrrd, or "
                 "raw with --raw); omitted: the built-in Cornell box");
  cmd.add_option("--res", o.resolution, "Image size WIDTHxHEIGHT")->capture_default_str();
  cmd.add_option(
         "--spp", o.spp,
         "Samples per pixel; 0: " + std::to_string(o.mesh_spp) +
             " for meshes, 1 for volumes. A pixel's path samples are the first points of a "
             "scrambled Sobol sequence, so powers of two (16, 64, 256) spread them most "
             "evenly (docs/noise.md)")
      ->capture_default_str();
  cmd.add_option("--bounces", o.bounces, "Maximum scattering events per path")
      ->capture_default_str();
  cmd.add_option("--clamp", o.clamp,
                 "Limit each camera sample's radiance so that its largest RGB component is at "
                 "most this (scaled, keeping its hue) before it is averaged into the pixel: "
                 "bounds fireflies at the cost of some energy in bright indirect light "
                 "(docs/noise.md); 0: off. Path kernels (path, direct)")
      ->capture_default_str();
  cmd.add_option("--frames", o.frames, "Number of frames to render")->capture_default_str();
  cmd.add_option("--camera", o.camera,
                 "Camera as ex,ey,ez,tx,ty,tz,ux,uy,uz,fov (eye, target, up, vertical fov in "
                 "degrees); default: the scene's first camera, else a three-quarter view from "
                 "outside that frames the scene's bounding box (see --up), a straight view "
                 "into a box that is open on one side, or a view from inside an enclosed "
                 "scene (Sponza); volumes: from the patient's front (docs/volumes.md). "
                 "`--camera default` takes that framing view even where the file has a "
                 "camera of its own");
  cmd.add_option("--up", o.up,
                 "The scene's up axis for the default camera and orbits: x, y or z, optionally "
                 "signed (+z, -y); auto: the file's own where it says (FBX UpAxis), else y for "
                 "meshes (glTF's convention), the superior axis (z) for volumes")
      ->capture_default_str();
  cmd.add_option("--camera-path", o.camera_path,
                 "Animation: fixed, orbit (100 frames per turn), orbit:PERIOD, or a keyframe "
                 "JSON file {\"keyframes\":[{\"frame\":0,\"eye\":[..],\"target\":[..],\"up\":[..],"
                 "\"fov\":45},...]}")
      ->capture_default_str();
  cmd.add_option("--ground", o.ground,
                 "Augmented reality: a shadow catcher standing for the real ground, the plane "
                 "AXIS=HEIGHT (y=0: where y is 0), diffuse, [,albedo=A] (0.5). The virtual "
                 "objects' shadows darken it; images become an RGBA layer (docs/ar.md). "
                 "Devices: " +
                     shadow_catcher_backends() + "; the path integrator");
  cmd.add_option("--poses", o.poses,
                 "Augmented reality: the capture's camera poses and intrinsics, one per frame "
                 "(JSON close to ARKit / ARCore exports; docs/ar.md); replaces --camera-path "
                 "and sets --frames to their count unless given");
  cmd.add_option("--devices", o.devices,
                 "auto (every core as one cpu device, and each GPU or accelerator OpenCL "
                 "offers; `multiray devices` lists them), or comma-separated devices, each "
                 "TYPE[:KEY=VALUE...], e.g. "
                 "cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.33. " +
                     device_keys_help())
      ->capture_default_str();
  // The common case in one word, as other renderers have it (pbrt --nthreads, Blender -t).
  cmd.add_option_function<int>(
         "--threads", [&o](const int& n) { o.devices = "cpu:threads=" + std::to_string(n); },
         "Shorthand for --devices cpu:threads=N: one CPU device of N threads (0: every "
         "hardware thread)")
      ->check(CLI::Range(0, 4096))
      ->excludes("--devices");
  cmd.add_option(
         "--env", o.env,
         "Light from outside the scene: a constant sky radiance V or R,G,B, or an "
         "equirectangular map FILE.hdr / FILE.exr (top row = up, see --up); auto = the "
         "scene's own, or daylight (a white sky of 0.3 and, with --sun auto, a sun; a sky of 1 "
         "without) when the "
         "scene has no light but emissive textures. The sky is sampled by next-event "
         "estimation with MIS")
      ->capture_default_str();
  cmd.add_option("--env-scale", o.env_scale, "Multiplies an --env map's radiance")
      ->capture_default_str();
  cmd.add_option(
         "--sun", o.sun,
         "A sun: auto (with the default daylight of a scene without lights: "
         "-40,55,3), off, or AZIMUTH,ELEVATION[,IRRADIANCE[,DIAMETER]], degrees round the up "
         "axis from the front towards the right and above the horizon (as the default "
         "camera's view), irradiance at normal incidence in W/m^2 in scene units "
         "(default 3; a white sky of 1 gives pi), angular diameter in degrees (0.53)")
      ->capture_default_str();
  cmd.add_option("--seed", o.seed, "Seed for all random numbers")->capture_default_str();
  {
    std::string help = "The denoiser's normal term (docs/noise.md, \"The filter\"):";
    for (const DenoiseNormalInfo& t : denoise_normal_terms())
      help += std::string(" ") + t.name + ": " + t.help + ";";
    help.back() = '.';
    cmd.add_option("--denoise-normal", o.denoise_normal, help)->capture_default_str();
  }
  cmd.add_option("--svgf-history", o.svgf_history,
                 "What svgf's next frame accumulates onto: filtered (the paper's, Schied et al. "
                 "2017: this frame after the first à-trous iteration) or accumulated (ours "
                 "until 2026-12-04: the unfiltered accumulation)")
      ->capture_default_str();
  cmd.add_flag("--allow-outside-paths", o.allow_outside_paths,
               "Let a scene file name files outside its own folder (buffers, images, material "
               "libraries); by default they are refused, with a warning or an error. Only "
               "regular files are ever read");
  cmd.add_option("--max-memory", o.max_memory,
                 "Refuse runs estimated to need more memory than this: auto (half of physical "
                 "memory) or a size such as 8G or 512M")
      ->capture_default_str();
  cmd.add_option("--views", o.views,
                 "Light-field grid of parallel views KxL (e.g. 3x3, 5x5), following the camera "
                 "path")
      ->capture_default_str();
  cmd.add_option("--view-spacing", o.view_spacing,
                 "Distance between neighbouring grid views: auto (1/30 of the camera's "
                 "distance to its target, the stereographers' 1/30 rule; stats.json's "
                 "view_spacing says what it came to) or a distance in scene units")
      ->capture_default_str();
  cmd.add_option("--stereo", o.stereo, "Render a stereo pair with this eye separation instead");
  cmd.add_option("--mapping", o.mapping,
                 "Multiview task mapping: strips (each device renders its share of every view's "
                 "shuffled strips) or views (whole views per device; uniform, static, dlb)");
  std::string kernels;
  for (const Choice& k : kernel_choices())
    kernels += (kernels.empty() ? "" : "; ") + k.name + ": " + k.help;
  cmd.add_option("--integrator", o.integrator,
                 "The kernel that renders; default: path for meshes, volume for volumes (" +
                     kernels_by_backend_help() + "). " + kernels);
  add_volume_options(cmd, o.volume);
  add_distributed_options(cmd, o.distributed);
  cmd.add_option("--ao-rays", o.ao_rays, "Occlusion rays per AO sample")->capture_default_str();
  cmd.add_option("--ao-distance", o.ao_distance,
                 "Occlusion range in scene units (0: 0.3 of the scene size)")
      ->capture_default_str();
  cmd.add_option("--sampling", o.sampling,
                 "uniform (--spp everywhere), adaptive (a first pass finds geometric edges; "
                 "edge pixels get --edge-spp samples, the others 1) or foveated (a fixed pattern "
                 "of samples, dense at the --gaze point and sparse around it; each pixel "
                 "interpolates its 8 nearest samples) or reproject (with several views: the "
                 "centre view is path-traced and moved into the others by its depth; only "
                 "what it cannot see there, the holes, is path-traced; Leria et al. 6.3)")
      ->capture_default_str();
  cmd.add_option("--edge-spp", o.edge_spp, "Samples of edge pixels with --sampling adaptive")
      ->capture_default_str();
  cmd.add_option("--reference-spacing", o.reference_spacing,
                 "With --sampling reproject: path-trace every K-th view from the centre, across "
                 "and down, in full and reproject from all of them (ours; fewer holes in large "
                 "grids); 0: the centre view alone (Leria et al.)")
      ->capture_default_str();
  cmd.add_option("--gaze", o.gaze,
                 "Foveated: gaze point X,Y in normalised screen coordinates, 0,0 top left")
      ->capture_default_str();
  cmd.add_option("--gaze-path", o.gaze_path,
                 "Foveated: fixed, or orbit[:PERIOD] (the gaze circles --gaze at radius 0.25, "
                 "one turn per PERIOD frames, default 100)")
      ->capture_default_str();
  cmd.add_option("--fovea-spp", o.foveation.fovea_spp,
                 "Foveated: samples per pixel at the gaze point; density(r) = max(periphery, "
                 "fovea / (1 + (r/r0)^2))")
      ->capture_default_str();
  cmd.add_option("--fovea-radius", o.foveation.fovea_radius,
                 "Foveated: r0, where the density halves, as a fraction of the image height")
      ->capture_default_str();
  cmd.add_option("--periphery-spp", o.foveation.periphery_spp,
                 "Foveated: the density's floor far from the gaze, samples per pixel")
      ->capture_default_str();
  cmd.add_option("--perturb", o.perturb,
                 "FRAME:DEVICE:SPEED, repeatable: from FRAME on, DEVICE runs at emulated SPEED");
}

}  // namespace multiray::app
