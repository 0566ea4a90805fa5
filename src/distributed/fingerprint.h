// What decides a worker's pixels that the master does not send with each frame. Every rank
// loads the scene and its lighting itself (unless --scene-from master) and keeps its own
// volume style; spp, seed, resolution and the cameras come from the master. A stale copy
// of a file on one machine would give frames that silently mix two scenes, so the worker's
// hello carries this fingerprint and the master refuses a worker whose differs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace multiray {

// One thing that decides pixels: a file's content (`what` names it: "scene file
// 'a.obj'", "file 'tex/b.png'"; `hash` its content_hash, core/scene_files.h), or options
// that change the loaded scene (`what` holds their values, `hash` 0).
struct FingerprintPart {
  std::string what;
  uint64_t hash = 0;
};
// In the order the run read them: equal runs give equal lists.
using PixelFingerprint = std::vector<FingerprintPart>;

// Empty when `worker` equals `master`; otherwise one line (no rank) saying what differs
// first: "'a.obj' differs (content hash 0123456789abcdef here, fedcba9876543210 there)",
// or which file or options one side has and the other not.
std::string fingerprint_difference(const PixelFingerprint& master, const PixelFingerprint& worker);

}  // namespace multiray
