// The command line's volume options (--tf, --step, --raw) and what they build: a Scene
// holding a volume, and the VolumeStyle its frames are rendered with.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/scene_cache.h"
#include "run/run_config.h"
#include "scene/scene.h"

namespace multiray {
struct VolumeStyle;
}

namespace multiray {

// True when `path` (with these options) names a volume: .nhdr, .nrrd, or any file when
// --raw describes it.
bool is_volume_input(const std::string& path, const VolumeOptions& o);

// Checks the options that need no file (step range, raw spec syntax); throws InputError.
void check_volume_options(const VolumeOptions& o);

// Loads the volume at `path` into a Scene with no triangles; `max_bytes` bounds the load
// (0: none). Throws InputError. A raw file (--raw) whose name gives another grid or type
// gives a warning; one whose name gives none, a note in `notes` (when given) that --raw's
// reading cannot be checked.
Scene load_volume_scene(const std::string& path, const VolumeOptions& o, bool allow_outside,
                        uint64_t max_bytes, std::vector<std::string>* notes = nullptr);

// The style of the frames: the transfer function --tf names (resolved on the volume), the
// block opacities, the step, `background` behind the volume. Builds the "volume"
// representation in `scenes` if needed. `tf_note` receives a line for the user when the
// transfer function was chosen automatically.
std::shared_ptr<const VolumeStyle> make_style(SceneCache& scenes, const VolumeOptions& o,
                                              Vec3 background, std::string* tf_note = nullptr);

}  // namespace multiray
