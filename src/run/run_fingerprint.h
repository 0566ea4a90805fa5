// A distributed run's fingerprint of what decides this rank's pixels (distributed/
// fingerprint.h): the files its loads read and the options that shape its scene.
#pragma once

#include <string>

#include "core/scene_files.h"
#include "distributed/fingerprint.h"
#include "run/run_config.h"

namespace multiray {

// Hooks `load` (LoadOptions::on_read) so that every file read through it — the scene file,
// each file it names, an environment map — is added to `fp` with its content hash, named
// relative to the folder of `scene_path` (else by its file name). `fp` must outlive the
// loads made with `load`.
void fingerprint_files(LoadOptions& load, const std::string& scene_path, PixelFingerprint& fp);

// Adds the rest: the options that change the loaded scene (lighting, --up; volumes: their
// style), and a volume's own files, which its loaders read outside LoadOptions.
// `scene_sent`: --scene-from master, where the scene arrives lit and only a volume's style
// is the worker's own.
void fingerprint_options(const RunConfig& o, bool volume_input, bool scene_sent,
                         PixelFingerprint& fp);

}  // namespace multiray
