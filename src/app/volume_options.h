// The command line's volume options (--tf, --step, --raw) and what they build: a Scene
// holding a volume, and the VolumeStyle its frames are rendered with.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "render/scene_cache.h"
#include "scene/scene.h"

namespace CLI {
class App;
}

namespace multiray {
struct VolumeStyle;
}

namespace multiray::app {

struct VolumeOptions {
  std::string tf = "auto";     // a preset name or a JSON file; auto: by voxel type
  float step = 0.5f;           // ray step, in voxel lengths
  std::string raw;             // "NXxNYxNZ:TYPE[...]" for a headerless .raw file
  double target_ms = 0;        // frame-time target; 0: none
  std::string adapt = "auto";  // none | last-frame | predict[:q=Q] | two-pass, a list for bench
  std::string adapt_space = "ray";  // ray | image | hybrid
  int prepass_stride = 4;           // pixels per pre-pass ray each way; 0: no prediction
  std::string sequence;             // interaction sequence file (sequence.h)
};

void add_volume_options(CLI::App& cmd, VolumeOptions& o);

// True when `path` (with these options) names a volume: .nhdr, .nrrd, or any file when
// --raw describes it.
bool is_volume_input(const std::string& path, const VolumeOptions& o);

// Checks the options that need no file (step range, raw spec syntax); throws InputError.
void check_volume_options(const VolumeOptions& o);

// Loads the volume at `path` into a Scene with no triangles; `max_bytes` bounds the load
// (0: none). Throws InputError.
Scene load_volume_scene(const std::string& path, const VolumeOptions& o, bool allow_outside,
                        uint64_t max_bytes);

// The style of the frames: the transfer function --tf names (resolved on the volume), the
// block opacities, the step, `background` behind the volume. Builds the "volume"
// representation in `scenes` if needed. `tf_note` receives a line for the user when the
// transfer function was chosen automatically.
std::shared_ptr<const VolumeStyle> make_style(SceneCache& scenes, const VolumeOptions& o,
                                              Vec3 background, std::string* tf_note = nullptr);

}  // namespace multiray::app
