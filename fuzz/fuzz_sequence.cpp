// Fuzz target of interaction sequences (`--sequence FILE.json`, run/sequence.h): the input
// is written to a file and read with load_sequence(), which must return a sequence or
// throw InputError. An accepted sequence must keep the promises of its header (frames in
// range and strictly increasing, zoom factors in [0.01, 100], at most 360 degrees a frame),
// and the camera path sequence_path() makes from it must give cameras camera_problem()
// accepts.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "run/sequence.h"
#include "scene/camera_check.h"

namespace {

// Fails unless the frames of `keys` strictly increase within 0..1000000.
template <class List>
void check_frames(const List& keys, const char* what) {
  for (size_t i = 0; i < keys.size(); ++i)
    if (keys[i].first < 0 || keys[i].first > 1000000 ||
        (i > 0 && keys[i].first <= keys[i - 1].first))
      multiray::fuzz::fail(std::string("load_sequence() accepts ") + what +
                           " frames that do not increase within 0..1000000");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  fuzz::FileSet files;
  files.main = std::string_view(reinterpret_cast<const char*>(data), size);
  const auto path = fuzz::write_files(files, "sequence.json");
  InteractionSequence seq;
  try {
    seq = load_sequence(path.string());
  } catch (const InputError&) {
    return 0;
  }
  if (seq.frames < 0 || seq.frames > 1000000) fuzz::fail("accepted frames out of 0..1000000");
  if (!(std::abs(seq.degrees_per_frame) <= 360)) fuzz::fail("accepted orbit over 360 degrees");
  check_frames(seq.zoom, "zoom");
  check_frames(seq.transfer_functions, "transfer function");
  for (const auto& [frame, factor] : seq.zoom)
    if (!(factor >= 0.01 && factor <= 100)) fuzz::fail("accepted a zoom factor out of range");
  for (int f : {-1, 0, 1, 7, 1000000}) (void)seq.tf_at(f);
  // The camera of a few frames (sequence_path makes one keyframe per frame).
  const int frames = seq.frames > 0 && seq.frames < 24 ? seq.frames : 24;
  const CameraPath camera_path = sequence_path(seq, Camera{}, frames);
  for (int f = 0; f < frames; f += 5)
    if (const std::string why = camera_problem(camera_path.at(f)); !why.empty())
      fuzz::fail("sequence_path() frame " + std::to_string(f) + " gives a camera that " +
                 "camera_problem() refuses: " + why);
  return 0;
}
