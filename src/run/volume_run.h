// What a volume run needs beyond the scene: the transfer-function styles (built when first
// needed, then shared), the frame-time targeting of each lane (--target-ms, --adapt,
// --adapt-space), the prediction advisor (Bruder et al. 2017) and the interaction sequence
// whose transfer-function switches change the settings between frames.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "balance/targeting.h"
#include "engine/frame_advisor.h"
#include "render/scene_cache.h"
#include "run/sequence.h"
#include "run/volume_setup.h"

namespace multiray {

class VolumeRun {
 public:
  // Checks the adaptation options and reads the sequence; throws InputError.
  VolumeRun(SceneCache& scenes, const VolumeOptions& o, Vec3 background);

  // The style of transfer function `tf` (a preset or file; "auto" by voxel type), built on
  // first use. Throws InputError for a bad transfer function.
  std::shared_ptr<const VolumeStyle> style(const std::string& tf);
  // The style of a transfer function given as JSON text (the file format of
  // docs/volumes.md; a live viewer's editor), never cached. Throws InputError.
  std::shared_ptr<const VolumeStyle> style_from_json(const std::string& json);
  // Settings schedule (Session::set_settings_schedule): the sequence's transfer function
  // at `frame`, or --tf.
  void apply(int frame, RenderSettings& settings);

  // One entry per --adapt mode (mode and its options; the target is --target-ms): each
  // balancer runs once per mode.
  const std::vector<balance::TargetingConfig>& modes() const { return modes_; }
  // The advisor of a lane adapting with modes()[mode], for `devices` devices.
  std::unique_ptr<FrameAdvisor> advisor(size_t mode, int devices) const;
  const InteractionSequence* sequence() const { return has_sequence_ ? &sequence_ : nullptr; }
  const VolumeOptions& options() const { return o_; }
  // Lines for the user (the transfer function chosen automatically, ...).
  std::vector<std::string> notes;
  // Bruder's Table 3, ms: building the block histograms (once per volume) and each style
  // (table and opacity histograms, once per transfer function).
  double blocks_ms = 0;
  std::vector<double> style_ms;

 private:
  SceneCache& scenes_;
  VolumeOptions o_;
  Vec3 background_;
  std::vector<balance::TargetingConfig> modes_;
  balance::AdaptSpace space_ = balance::AdaptSpace::automatic;
  InteractionSequence sequence_;
  bool has_sequence_ = false;
  std::map<std::string, std::shared_ptr<const VolumeStyle>> styles_;
};

}  // namespace multiray
