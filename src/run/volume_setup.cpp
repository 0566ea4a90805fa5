#include "run/volume_setup.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/scene_files.h"
#include "engine/cost_model.h"
#include "render/volume_raycaster.h"
#include "volume/load_volume.h"
#include "volume/transfer_function.h"

namespace multiray {

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
  try {
    parse_cost_model(o.cost_model);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--cost-model: ") + e.what());
  }
  if (!(o.reference_step == 0 || (o.reference_step >= kMinStep && o.reference_step <= kMaxStep)))
    throw InputError("--reference-step must be 0 (none) or in [0.01, 64] voxel lengths");
}

Scene load_volume_scene(const std::string& path, const VolumeOptions& o, bool allow_outside,
                        uint64_t max_bytes, std::vector<std::string>* notes) {
  VolumeLoadOptions load;
  load.allow_outside = allow_outside;
  load.max_bytes = max_bytes;
  // The CPU raycaster's narrow copy and skip cells (2 + 0.125 bytes a voxel).
  load.kept_bytes_per_voxel = kVoxelGridBytesPerVoxel + 1;
  std::shared_ptr<Volume> volume;
  if (o.raw.empty()) {
    volume = std::make_shared<Volume>(load_volume(path, load));
  } else {
    const RawVolumeSpec spec = parse_raw_spec(o.raw);
    volume = std::make_shared<Volume>(load_raw_volume(path, spec, load));
    // Same size, other meaning (2x2x2 int16 or 4x4x2 uint8) cannot be seen in the data.
    bool described = false;
    const std::string mismatch = raw_name_mismatch(path, spec, &described);
    if (!mismatch.empty())
      detail::warn(LoadOptions{}, path, mismatch);
    else if (!described && notes)
      notes->push_back("'" + volume->name + "' is read as --raw " + o.raw +
                       " says; a raw file's bytes cannot confirm its grid and type");
  }
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
  // Not a preset and no such file: most likely a mistyped preset, so say which there are.
  std::error_code ec;
  if (!preset && !std::filesystem::exists(name, ec))
    throw InputError("--tf '" + name + "' is neither a preset (" + preset_list() +
                     ") nor a transfer-function file");
  const TransferFunction tf =
      preset ? transfer_preset(name, vs.volume) : resolve(load_transfer_function(name), vs.volume);
  auto style = make_volume_style(vs, tf, o.step);
  style->background = background;
  return style;
}

}  // namespace multiray
