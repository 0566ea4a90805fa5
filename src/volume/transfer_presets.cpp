// Built-in transfer functions. CT presets are in Hounsfield units: air -1000, fat about
// -100, soft tissue 20..80, bone above about 300. The soft-tissue one puts its ramp over
// the cranium file's own display window (level -18, width 406: -221..185 HU).
#include <string>
#include <vector>

#include "core/error.h"
#include "volume/transfer_function.h"

namespace multiray {

namespace {

struct Preset {
  const char* name;
  TfUnits units;
  std::vector<TfPoint> points;
};

const std::vector<Preset>& presets() {
  static const std::vector<Preset> all = {
      // Bone opaque and white; everything below 250 HU transparent.
      {"ct-bone",
       TfUnits::data,
       {{-1024, {0, 0, 0}, 0},
        {250, {0.8f, 0.7f, 0.6f}, 0},
        {400, {0.95f, 0.9f, 0.8f}, 0.3f},
        {1000, {1, 1, 0.95f}, 0.8f},
        {3071, {1, 1, 1}, 0.95f}}},
      // Fat and air transparent, soft tissue faint and reddish across the window,
      // bone (above 300 HU) brighter and denser.
      {"ct-soft-tissue",
       TfUnits::data,
       {{-1024, {0, 0, 0}, 0},
        {-221, {0.55f, 0.25f, 0.2f}, 0},
        {-18, {0.85f, 0.5f, 0.4f}, 0.04f},
        {185, {0.95f, 0.75f, 0.65f}, 0.12f},
        {300, {1, 0.95f, 0.85f}, 0.5f},
        {3071, {1, 1, 1}, 0.8f}}},
      // Contrast-filled vessels (the bright values) red to white; the background (0 and
      // the lowest tenth of the range) fully transparent, so empty space can be skipped.
      {"angio",
       TfUnits::fraction,
       {{0, {0, 0, 0}, 0},
        {0.1f, {0.5f, 0.05f, 0.05f}, 0},
        {0.3f, {0.85f, 0.25f, 0.15f}, 0.3f},
        {0.6f, {1, 0.75f, 0.5f}, 0.7f},
        {1, {1, 1, 1}, 0.9f}}},
      // A linear ramp: black and transparent at the minimum, white at the maximum.
      {"grey", TfUnits::fraction, {{0, {0, 0, 0}, 0}, {1, {1, 1, 1}, 0.25f}}},
  };
  return all;
}

}  // namespace

std::vector<std::string> transfer_preset_names() {
  std::vector<std::string> names;
  for (const Preset& p : presets()) names.push_back(p.name);
  return names;
}

TransferFunction transfer_preset(const std::string& name, const Volume& volume) {
  for (const Preset& p : presets()) {
    if (name != p.name) continue;
    TransferFunction tf;
    tf.name = p.name;
    tf.units = p.units;
    tf.points = p.points;
    return resolve(tf, volume);
  }
  std::string list;
  for (const std::string& n : transfer_preset_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown transfer function preset '" + name + "' (presets: " + list + ")");
}

}  // namespace multiray
