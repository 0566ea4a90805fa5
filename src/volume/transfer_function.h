// 1-D transfer functions for the volume raycaster (Bruder, Frey & Ertl 2017, §3: colour
// and opacity from the data value): RGBA piecewise linear over data values, with a
// lookup table baked for the kernels and the opacity correction for a step length.
//
// JSON file format (load_transfer_function; also docs/volumes.md):
//   {"name": "bone",                      optional, a label
//    "units": "data" | "fraction",        optional, default "data"
//    "reference_step": 1,                 optional, > 0: opacity is per this many voxel
//                                         lengths (default 1)
//    "points": [{"value": -1024, "color": [0, 0, 0], "opacity": 0}, ...]}
// "points": at least 2, values strictly increasing; colours linear RGB in [0, 1]; opacity
// in [0, 1]. "fraction" values are in [0, 1]: fractions of [min_value, max_value] of the
// volume the function is bound to (resolve()). Any other key is an error.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/math.h"
#include "volume/volume.h"

namespace multiray {

struct TfPoint {
  float value = 0;    // data value (or fraction, see TfUnits)
  Vec3 color;         // linear RGB in [0, 1]
  float opacity = 0;  // in [0, 1], per reference step
};

enum class TfUnits { data, fraction };

// Between points colour and opacity are linear in the value; below the first and above
// the last point they keep the end point's colour and opacity.
struct TransferFunction {
  std::string name;
  std::vector<TfPoint> points;  // >= 2, values strictly increasing
  TfUnits units = TfUnits::data;
  float reference_step = 1;  // opacity is per this distance, in voxel lengths
};

// Largest number of points a transfer function may have.
constexpr size_t kMaxTfPoints = 4096;
// Largest transfer function file read, in bytes.
constexpr uint64_t kMaxTfFileBytes = uint64_t(1) << 20;

// Reads a JSON transfer function (format above). Throws InputError "<path>: <problem>",
// one line, for a file that is not a regular file, over kMaxTfFileBytes, not JSON, or
// breaks any rule above.
TransferFunction load_transfer_function(const std::string& path);
// The same from JSON text; `source` names it in messages.
TransferFunction parse_transfer_function(const std::string& json, const std::string& source);

// Throws InputError "<source>: <problem>" unless `tf` follows the rules above.
void check_transfer_function(const TransferFunction& tf, const std::string& source);

// `tf` in data units for `volume`: fraction f becomes min + f * (max - min) (for a
// constant volume, min + f). A data-unit function is returned unchanged.
TransferFunction resolve(const TransferFunction& tf, const Volume& volume);

// Colour (rgb) and opacity (a) of `tf` at `value`, in the function's own units.
std::array<float, 4> evaluate(const TransferFunction& tf, float value);

// Exact maximum of the opacity of `tf` over [lo, hi] (lo <= hi): the larger of the ends
// and every point strictly inside. 0 exactly iff the function is 0 on the whole interval.
float max_opacity(const TransferFunction& tf, float lo, float hi);

// Presets, in the units named: "ct-bone", "ct-soft-tissue" (Hounsfield units),
// "angio" and "grey" (fractions). transfer_preset returns it resolved for `volume`.
// An unknown name throws InputError listing the names.
std::vector<std::string> transfer_preset_names();
TransferFunction transfer_preset(const std::string& name, const Volume& volume);

// `tf` sampled at n evenly spaced values over [lo, hi] for the kernels: rgba[i] is
// evaluate(tf, lo + (hi - lo) * i / (n - 1)); alpha is per reference step, colour is not
// premultiplied. Between entries lookup() interpolates linearly, so the table can be
// non-zero up to one entry spacing (hi - lo) / (n - 1) outside the function's non-zero
// range.
struct TransferTable {
  float lo = 0, hi = 1;
  float reference_step = 1;  // copied from the function, in voxel lengths
  std::vector<std::array<float, 4>> rgba;

  // Linear interpolation between entries; values outside [lo, hi] (and NaN) are clamped.
  std::array<float, 4> lookup(float value) const;
};

// Bakes `tf` (in data units: resolve() first) over [lo, hi] into n entries, 2 <= n <=
// 1 << 20. hi <= lo (a constant volume) gives a table over [lo, lo + 1]. Throws
// std::invalid_argument for non-finite lo or hi or n out of range.
TransferTable bake(const TransferFunction& tf, float lo, float hi, int n = 4096);

// Opacity for a step of `step_over_reference` reference steps given opacity `alpha` per
// reference step: 1 - (1 - alpha)^(step / reference) (the opacity correction of Engel et
// al., "Real-Time Volume Graphics", 2006; Bruder et al. 2017 need it when they tune the
// step size). alpha is clamped to [0, 1]; step <= 0 gives 0.
float corrected_alpha(float alpha, float step_over_reference);

}  // namespace multiray
