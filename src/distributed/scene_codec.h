// A whole Scene as bytes, for `--scene-from master`: the master sends the scene it loaded
// (lighting applied) to every worker, so workers need no copy of the files. Meshes,
// materials, textures, the environment, cameras and volumes all travel; the receiving end
// checks the result as a loader would (validate(), texture and volume sizes).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace multiray::remote {

std::vector<uint8_t> encode_scene(const Scene& scene);
// Throws WireError for bytes that do not parse, InputError for a scene that does not
// validate.
Scene decode_scene(const std::vector<uint8_t>& bytes);

}  // namespace multiray::remote
