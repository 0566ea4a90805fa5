// Parsing and checking of the CLI's values, and building a ready-to-render setup from them.
// Everything here throws InputError with a one-line message on bad input.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/distributed.h"
#include "app/volume_options.h"
#include "app/volume_run.h"
#include "engine/frame_views.h"
#include "engine/session.h"
#include "render/scene_cache.h"
#include "scene/camera_path.h"
#include "scene/camera_rig.h"
#include "scene/scene.h"

namespace multiray::app {

// Options shared by `render` and `bench`.
struct CommonOptions {
  std::string scene_path;  // empty: built-in Cornell box
  std::string resolution = "640x360";
  int spp = 0;        // 0: mesh_spp for meshes, 1 for volumes
  int mesh_spp = 16;  // what --spp 0 means for meshes (bench: 4)
  int bounces = 8;
  int frames = 1;
  std::string camera;                     // "ex,ey,ez,tx,ty,tz,ux,uy,uz,fov" or empty
  std::string up = "auto";                // [+-]x|y|z; auto: y for meshes, z for volumes
  std::string camera_path = "fixed";      // fixed | orbit | orbit:PERIOD | FILE.json
  std::string devices = "cpu:threads=0";  // threads=0: all hardware threads
  std::string seed = "0";            // a whole number in [0, 2^64); parsed strictly in make_setup
  std::string env = "auto";          // auto | V | R,G,B | FILE.hdr|.exr (app/lighting_options.h)
  double env_scale = 1.0;            // multiplies an environment map
  std::string sun = "auto";          // auto | off | AZ,EL[,IRRADIANCE[,DIAMETER]]
  std::vector<std::string> perturb;  // FRAME:DEVICE:SPEED
  std::string views = "1x1";         // KxL light-field grid
  float view_spacing = 0.2f;         // between grid views, scene units
  float stereo = 0.0f;               // > 0: a stereo pair this far apart (overrides views)
  std::string mapping;               // strips | views | empty (the balancer's own layout)
  std::string integrator;            // a CPU kernel's name (render/kernel.h); empty: by scene
  VolumeOptions volume;              // --tf, --step, --raw
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
  DistributedOptions distributed;    // --distributed and its options (app/distributed.h)
};

// Parses --gaze "X,Y" (each in [0, 1]) and --gaze-path (fixed | orbit | orbit:PERIOD).
GazePath parse_gaze(const std::string& gaze, const std::string& path);

struct Resolution {
  int width = 0, height = 0;
};

Resolution parse_resolution(const std::string& text);
uint64_t parse_seed(const std::string& text);
Camera parse_camera(const std::string& text);
// --up: "auto" (+y for meshes, +z for volumes, whose slices stack along z) or an axis
// x, y, z with an optional sign.
Vec3 parse_up(const std::string& text, bool volume);
// --exposure in stops, [-20, 20].
float parse_exposure(double ev);
// --tone: filmic, clamp, or auto (filmic for meshes; clamp for volumes, whose raycaster
// already writes display colours in [0, 1]).
ToneCurve parse_tone(const std::string& text, bool volume);
// Adds the layout `mapping` asks for to a balancer spec: strips (every device renders its
// share of every view's shuffled strips) or views (whole views per device). Empty: spec
// unchanged. Throws InputError when the balancer has no such layout, or a malformed spec
// as a bad value of `option` (the command-line option that gave the spec).
std::string apply_mapping(const std::string& balancer_spec, const std::string& mapping,
                          const std::string& option = "--balancer");

std::vector<Perturbation> parse_perturbations(const std::vector<std::string>& items,
                                              int device_count);

// The loaded scene and everything derived from the options; owns the devices.
struct Setup {
  // A distributed run's MPI side (null otherwise). First, so that it outlives the devices
  // (the master's remote devices use its transport).
  std::shared_ptr<Cluster> cluster;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneCache> scenes;  // the representations the devices render
  std::vector<std::unique_ptr<Device>> devices;
  CameraPath path;
  std::unique_ptr<FrameViews> views;  // rig, output size and sampling of every frame
  Resolution res;
  RenderSettings settings;
  std::vector<Perturbation> perturbations;
  std::vector<std::string> notes;     // things the user should know (e.g. a sky was added)
  Camera camera;                      // the base camera of the path (before any animation)
  std::string camera_source;          // "--camera", "scene" (its first camera) or "default"
  Vec3 up{0, 1, 0};                   // the up axis --up resolved to
  std::shared_ptr<VolumeRun> volume;  // volumes only: styles, adaptation, sequence

  std::vector<Device*> device_ptrs() const;
  // A session over the devices with one lane per balancer spec (each already checked) and,
  // for volumes, per --adapt mode (spec-major: spec 0 with every mode, then spec 1, ...),
  // each lane with its own prediction advisor. Bad specs are reported as coming from
  // `option`.
  std::unique_ptr<Session> make_session(const std::vector<std::string>& balancer_specs,
                                        const std::string& option = "--balancer") const;
  // The name of each lane make_session(specs) makes: the spec, plus " adapt=MODE" when a
  // volume run adapts in more than one way.
  std::vector<std::string> lane_labels(const std::vector<std::string>& balancer_specs) const;
};

// Memory a run is estimated to need before it takes it, in bytes: the scene (from its file
// size: loaded geometry, BVH and shading records are within ~12x a mesh file) and the
// frames (every view's float image in the session's buffers, `lanes` of them, plus
// per-pixel sample data of irregular sampling). A refusal beats an out-of-memory kill.
struct MemoryEstimate {
  double scene_bytes = 0, frame_bytes = 0;
  double total() const { return scene_bytes + frame_bytes; }
};
MemoryEstimate estimate_memory(const CommonOptions& o, int views, int width, int height,
                               int lanes);
// --max-memory: "auto" (half of physical memory) or a size like 8G, 512M, 100000 (bytes).
double parse_memory_limit(const std::string& text);

// Strict numeric parsing: the whole token must be a finite number, else InputError
// "<what>: '<tok>' is not a number".
double to_number(const std::string& tok, const std::string& what);
// `s` cut at every `sep` (a trailing separator gives a final empty part).
std::vector<std::string> split(const std::string& s, char sep);

// A worker rank of a distributed run (s.cluster, not the master): serves the master over
// s.devices until it says quit; returns the exit code.
int serve_as_worker(Setup& s);

// Validates every option before loading anything expensive (the memory estimate
// included, for `lanes` balancers), then loads the scene and creates the devices.
// `before_load`, if given, runs after the options are checked and before the scene loads
// (e.g. preparing the output folder: its refusal then costs nothing).
// With --distributed, MPI starts here; on the master, s.devices are then one remote device
// per worker (then its own, with --master-renders); a worker's fault in setting up is
// reported by the master as "rank R: ...", and the worker ends with QuietExit.
Setup make_setup(const CommonOptions& o, int lanes = 1,
                 const std::function<void()>& before_load = {});

}  // namespace multiray::app
