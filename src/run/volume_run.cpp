#include "run/volume_run.h"

#include <stdexcept>

#include "core/clock.h"
#include "core/error.h"
#include "engine/volume_advisor.h"
#include "render/volume_raycaster.h"
#include "util/spec.h"
#include "volume/transfer_function.h"

namespace multiray {

VolumeRun::VolumeRun(SceneCache& scenes, const VolumeOptions& o, Vec3 background)
    : scenes_(scenes), o_(o), background_(background) {
  Stopwatch clock;
  volume_scene(scenes);  // the block histograms, built here so that their time is known
  blocks_ms = clock.elapsed_ms();
  try {
    space_ = balance::parse_adapt_space(o.adapt_space);
    if (o.adapt == "auto") {
      modes_.emplace_back().mode =
          o.target_ms > 0 ? balance::AdaptMode::predict : balance::AdaptMode::none;
    } else {
      for (const std::string& m : split_spec_list(o.adapt))
        balance::parse_adapt(m, modes_.emplace_back());
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--adapt: ") + e.what());
  }
  if (modes_.empty()) throw InputError("--adapt is empty");
  for (const balance::TargetingConfig& m : modes_)
    if (m.mode != balance::AdaptMode::none && !(o.target_ms > 0))
      throw InputError("--adapt " + balance::adapt_name(m) +
                       " needs a frame-time target (--target-ms)");
  if (!o.sequence.empty()) {
    sequence_ = load_sequence(o.sequence);
    has_sequence_ = true;
    for (const auto& [frame, tf] : sequence_.transfer_functions) style(tf);  // check them now
  }
}

std::shared_ptr<const VolumeStyle> VolumeRun::style(const std::string& tf) {
  auto it = styles_.find(tf);
  if (it != styles_.end()) return it->second;
  Stopwatch clock;
  VolumeOptions o = o_;
  o.tf = tf;
  std::string note;
  auto made = make_style(scenes_, o, background_, &note);
  style_ms.push_back(clock.elapsed_ms());
  if (!note.empty()) notes.push_back(note);
  return styles_[tf] = made;
}

std::shared_ptr<const VolumeStyle> VolumeRun::style_from_json(const std::string& json) {
  const VolumeScene& vs = volume_scene(scenes_);
  const TransferFunction tf = resolve(parse_transfer_function(json, "the viewer"), vs.volume);
  auto made = make_volume_style(vs, tf, o_.step);
  made->background = background_;
  return made;
}

void VolumeRun::apply(int frame, RenderSettings& settings) {
  const std::string& tf = has_sequence_ ? sequence_.tf_at(frame) : std::string();
  settings.volume_style = style(tf.empty() ? o_.tf : tf);
}

std::unique_ptr<FrameAdvisor> VolumeRun::advisor(size_t mode, int devices) const {
  if (o_.prepass_stride == 0) return nullptr;
  VolumeAdvisorConfig c;
  c.targeting = modes_.at(mode);
  c.targeting.target_ms = o_.target_ms > 0 ? o_.target_ms : 1;  // mode none ignores it
  c.targeting.space = space_;
  c.prepass_stride = o_.prepass_stride;
  c.cost_model = parse_cost_model(o_.cost_model);
  return std::make_unique<VolumeAdvisor>(volume_scene(scenes_), devices, c);
}

}  // namespace multiray
