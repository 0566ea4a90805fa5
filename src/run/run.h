// A run built from its RunConfig: the loaded scene, its device representations, the
// devices, the camera path and views, and a Session over them (one lane per balancer).
// build_run() checks every value before it loads anything, and throws InputError with a
// one-line message on bad input. The CLI, the bench programs, the fuzz targets and the
// Python module all start a run here.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "balance/auto_choice.h"
#include "core/scene_files.h"
#include "distributed/cluster.h"
#include "distributed/fingerprint.h"
#include "engine/frame_views.h"
#include "engine/session.h"
#include "render/scene_cache.h"
#include "run/parse_options.h"
#include "run/run_config.h"
#include "run/volume_run.h"
#include "run/volume_setup.h"
#include "scene/camera_path.h"
#include "scene/camera_rig.h"
#include "scene/scene.h"

namespace multiray {

// The loaded scene and everything derived from the options; owns the devices.
struct Run {
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
  std::vector<std::string> notes;  // things the user should know (e.g. a sky was added)
  Camera camera;                   // the base camera of the path (before any animation)
  // "--camera", "scene" (its first camera), "default" (framed from outside) or
  // "default-interior" (inside an enclosed scene; render/default_view.h).
  std::string camera_source;
  Vec3 up{0, 1, 0};        // the up axis --up resolved to
  float view_spacing = 0;  // between grid views, scene units (0: one view)
  // --denoise as resolved for this run (none: no denoiser); make_session passes it on.
  DenoiseMethod denoise = DenoiseMethod::none;
  DenoiseParams denoise_params;  // --denoise-normal's form; make_session passes them on
  // Whether the run could record feature buffers, which a denoiser needs (the path
  // integrator, uniform or adaptive sampling, no --ground): the viewer's denoise toggle.
  bool can_record_features = false;
  std::shared_ptr<VolumeRun> volume;  // volumes only: styles, adaptation, sequence
  // What `--balancer auto` decides from (build_run: the devices, the link, the workload),
  // and --mapping, applied to what it picks.
  balance::AutoInputs auto_inputs;
  std::string mapping;
  // Charges an image a command decodes while the run renders (render's --background)
  // against --max-memory with the scene's own images: `keep` bytes for as long as the run
  // lives, `transient` while it is decoded. Throws InputError (memory_refusal) when they
  // would not fit; set by build_run (memory_guarded_load's reserve_image).
  std::function<void(const std::string& what, uint64_t keep, uint64_t transient)> reserve_image;
  // A distributed run: what decides this rank's pixels besides what the master sends
  // (the files its loads read, the options that shape its scene): run/run_fingerprint.h.
  PixelFingerprint fingerprint;

  std::vector<Device*> device_ptrs() const;
  // A session over the devices with one lane per balancer spec (each already checked) and,
  // for volumes, per --adapt mode (spec-major: spec 0 with every mode, then spec 1, ...),
  // each lane with its own prediction advisor. Bad specs are reported as coming from
  // `option`.
  std::unique_ptr<Session> make_session(const std::vector<std::string>& balancer_specs,
                                        const std::string& option = "--balancer") const;
  // `spec`, or for "auto" the spec choose_balancer(auto_inputs) picks (with --mapping
  // applied), and that choice in `*choice` if given. make_session resolves every spec so;
  // commands call it first to report the choice. Throws InputError against `option`.
  std::string resolve_balancer(const std::string& spec, balance::AutoChoice* choice = nullptr,
                               const std::string& option = "--balancer") const;
  // The name of each lane make_session(specs) makes: the spec, plus " adapt=MODE" when a
  // volume run adapts in more than one way.
  std::vector<std::string> lane_labels(const std::vector<std::string>& balancer_specs) const;
};

// --frames: InputError unless in 1..1000000 (build_run checks it; a command whose own
// options depend on it, such as bench's --warmup, checks it first).
void check_frame_count(int frames);

// The camera path a --camera-path value names ("fixed", "orbit", "orbit:PERIOD" or a JSON
// keyframe file) around the run's base camera. Throws InputError.
CameraPath camera_path_option(const std::string& value, const Camera& base);

// Memory a run is estimated to need before it takes it, in bytes: the scene (from its file
// size: loaded geometry, BVH and shading records are within ~12x a mesh file) and the
// frames (every view's float image in the session's buffers, `lanes` of them, plus
// per-pixel sample data of irregular sampling), and what the command keeps per frame
// (RunConfig::kept_bytes_per_frame × frames). A refusal beats an out-of-memory kill.
struct MemoryEstimate {
  double scene_bytes = 0, frame_bytes = 0, record_bytes = 0;
  double total() const { return scene_bytes + frame_bytes + record_bytes; }
};
MemoryEstimate estimate_memory(const RunConfig& o, int views, int width, int height, int lanes);
// --max-memory: "auto" (half of physical memory) or a size like 8G, 512M, 100000 (bytes).
double parse_memory_limit(const std::string& text);
// The one refusal of a command over --max-memory, for an InputError: "this run needs
// about 51.5 GB (<parts>), more than the 12.6 GB allowed (--max-memory; default: half of
// physical memory)". `need` and `limit` in bytes; `parts` says what the estimate holds.
std::string memory_refusal(double need, const std::string& parts, double limit);
// Loader options that keep a load within `limit` bytes when `need` are already counted:
// assimp's formats are read first in a child under the rest (parser_memory_limit), and each
// decoded image is charged from its header before it is decoded (reserve_image), refused
// with memory_refusal(..., parts(images), limit) once it would pass the limit.
LoadOptions memory_guarded_load(double need, double limit,
                                const std::function<std::string(double images)>& parts);

// A worker rank of a distributed run (s.cluster, not the master): serves the master over
// s.devices until it says quit; returns the exit code.
int serve_as_worker(Run& s);

// What the rules of `--balancer auto` see of a built run (run/auto_balancer.cpp).
balance::AutoInputs gather_auto_inputs(const Run& s, const RunConfig& o);

// Validates every option before loading anything expensive (the memory estimate
// included, for `lanes` balancers), then loads the scene and creates the devices.
// `before_load`, if given, runs after the options are checked and before the scene loads
// (e.g. preparing the output folder: its refusal then costs nothing).
// With --distributed, MPI starts here; on the master, s.devices are then one remote device
// per worker (then its own, with --master-renders); a worker's fault in setting up is
// reported by the master as "rank R: ...", and the worker ends with QuietExit.
Run build_run(const RunConfig& o, int lanes = 1, const std::function<void()>& before_load = {});

}  // namespace multiray
