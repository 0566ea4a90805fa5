// Interaction sequences for volume benchmarks (Bruder et al. 2017 drive their experiments
// with recorded interaction: orbiting, zooming, and transfer-function switches, the sudden
// changes that defeat last-frame adaptation). A JSON file:
//   {"frames": 300,                                   optional: the run's default length
//    "orbit_degrees_per_frame": 1.2,                  rotation about the camera's up axis
//    "zoom": [[0, 1.0], [150, 0.6], [300, 1.0]],      eye distance factor, linear between
//    "transfer_functions": [[0, "ct-bone"], [100, "ct-soft-tissue"], [200, "tf.json"]]}
// Every key is optional; frames of "zoom" and "transfer_functions" strictly increase.
// Transfer functions are presets or JSON files (relative to the sequence file's folder).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "scene/camera_path.h"

namespace multiray {

struct InteractionSequence {
  int frames = 0;  // 0: not given
  double degrees_per_frame = 0;
  std::vector<std::pair<int, double>> zoom;
  std::vector<std::pair<int, std::string>> transfer_functions;  // names resolved to paths

  // The transfer function in effect at `frame` (empty when the file names none).
  const std::string& tf_at(int frame) const;
};

// Reads and checks a sequence file; InputError "<path>: <problem>" (one line) otherwise.
InteractionSequence load_sequence(const std::string& path);

// The camera of every frame in [0, frames): `base` orbited about its up axis through its
// target and zoomed, as keyframes (one per frame).
CameraPath sequence_path(const InteractionSequence& seq, const Camera& base, int frames);

}  // namespace multiray
