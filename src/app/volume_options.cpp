#include "app/volume_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "render/volume_raycaster.h"
#include "volume/load_volume.h"
#include "volume/transfer_function.h"

namespace multiray::app {

namespace {
// Steps below a hundredth of a voxel only multiply the cost (a 256^3 volume would take
// tens of thousands of samples per ray); above 64 voxels nothing is left to see.
constexpr float kMinStep = 0.01f, kMaxStep = 64.0f;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string preset_list() {
  std::string names;
  for (const std::string& n : transfer_preset_names()) names += (names.empty() ? "" : ", ") + n;
  return names;
}
}  // namespace

void add_volume_options(CLI::App& cmd, VolumeOptions& o) {
  cmd.add_option("--tf", o.tf,
                 "Volumes: transfer function, a preset (" + preset_list() +
                     ") or a JSON file (docs/volumes.md); auto: ct-bone for 16-bit data, angio "
                     "for 8-bit")
      ->capture_default_str();
  cmd.add_option("--step", o.step,
                 "Volumes: ray step in voxel lengths (the shortest spacing), in [0.01, 64]")
      ->capture_default_str();
  cmd.add_option("--target-ms", o.target_ms,
                 "Volumes: frame-time target in ms for --adapt (0: none)")
      ->capture_default_str();
  cmd.add_option(
         "--adapt", o.adapt,
         "Volumes: frame-time targeting: none, last-frame (scale quality by the last "
         "frame's time), predict (Bruder et al.: choose quality from the predicted "
         "time; predict:q=Q scales predictions by the Q-quantile of recent measured/predicted "
         "ratios, e.g. q=0.9), two-pass (a quarter-quality pass, then a second pass "
         "filling the budget if the first took under half of it); auto: predict with --target-ms, "
         "else none. bench takes a list and runs "
         "every balancer once per mode")
      ->capture_default_str();
  cmd.add_option("--adapt-space", o.adapt_space,
                 "Volumes: what --adapt changes: ray (the step), image (the resolution, "
                 "upsampled) or hybrid (both)")
      ->capture_default_str();
  cmd.add_option("--prepass-stride", o.prepass_stride,
                 "Volumes: one prediction pre-pass ray per NxN pixels (0: no prediction; "
                 "balancers then split by area)")
      ->capture_default_str();
  cmd.add_option("--sequence", o.sequence,
                 "Volumes: interaction sequence JSON (orbit, zoom, transfer-function switches "
                 "at given frames; docs/volumes.md); replaces --camera-path");
  cmd.add_option("--raw", o.raw,
                 "Volumes: read the scene file as headerless voxels "
                 "NXxNYxNZ:TYPE[:be|:le][:spacing=SX,SY,SZ], TYPE uint8, int8, uint16 or int16");
}

bool is_volume_input(const std::string& path, const VolumeOptions& o) {
  if (!o.raw.empty()) return true;
  const std::string ext = lower_extension(path);
  return ext == ".nhdr" || ext == ".nrrd";
}

void check_volume_options(const VolumeOptions& o) {
  if (!(o.step >= kMinStep && o.step <= kMaxStep))
    throw InputError("--step must be in [0.01, 64] voxel lengths");
  if (!(o.target_ms == 0 || (o.target_ms >= 0.1 && o.target_ms <= 1e6)))
    throw InputError("--target-ms must be 0 (none) or in [0.1, 1e6] ms");
  if (o.prepass_stride < 0 || o.prepass_stride > 64)
    throw InputError("--prepass-stride must be in 0..64 (0: no prediction)");
  if (!o.raw.empty()) parse_raw_spec(o.raw);
}

Scene load_volume_scene(const std::string& path, const VolumeOptions& o, bool allow_outside,
                        uint64_t max_bytes) {
  VolumeLoadOptions load;
  load.allow_outside = allow_outside;
  load.max_bytes = max_bytes;
  auto volume =
      std::make_shared<Volume>(o.raw.empty() ? load_volume(path, load)
                                             : load_raw_volume(path, parse_raw_spec(o.raw), load));
  Scene scene;
  scene.name = volume->name;
  scene.volume = std::move(volume);
  validate(scene);
  return scene;
}

std::shared_ptr<const VolumeStyle> make_style(SceneCache& scenes, const VolumeOptions& o,
                                              Vec3 background, std::string* tf_note) {
  const VolumeScene& vs = volume_scene(scenes);
  std::string name = o.tf;
  if (name == "auto") {
    const bool wide = vs.volume.type == VoxelType::u16 || vs.volume.type == VoxelType::i16;
    name = wide ? "ct-bone" : "angio";
    if (tf_note)
      *tf_note = "transfer function: preset " + name + " (--tf; presets: " + preset_list() + ")";
  }
  const auto& presets = transfer_preset_names();
  const bool preset = std::find(presets.begin(), presets.end(), name) != presets.end();
  const TransferFunction tf =
      preset ? transfer_preset(name, vs.volume) : resolve(load_transfer_function(name), vs.volume);
  auto style = make_volume_style(vs, tf, o.step);
  style->background = background;
  return style;
}

}  // namespace multiray::app
