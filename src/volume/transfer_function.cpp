#include "volume/transfer_function.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "core/scene_files.h"
#include "volume/volume_input.h"

namespace multiray {

using detail::fail;

namespace {

bool by_value(float v, const TfPoint& p) { return v < p.value; }

std::array<float, 4> rgba(const TfPoint& p) {
  return {p.color.x, p.color.y, p.color.z, p.opacity};
}

bool in_unit(float x) { return x >= 0 && x <= 1; }

}  // namespace

void check_transfer_function(const TransferFunction& tf, const std::string& source) {
  if (tf.points.size() < 2 || tf.points.size() > kMaxTfPoints)
    fail(source, "a transfer function needs 2.." + std::to_string(kMaxTfPoints) + " points, not " +
                     std::to_string(tf.points.size()));
  if (!(std::isfinite(tf.reference_step) && tf.reference_step > 0 && tf.reference_step <= 1e3f))
    fail(source, "reference_step must be a number in (0, 1000]");
  for (size_t i = 0; i < tf.points.size(); ++i) {
    const TfPoint& p = tf.points[i];
    const std::string where = "point " + std::to_string(i) + ": ";
    if (!std::isfinite(p.value)) fail(source, where + "value is not a finite number");
    if (tf.units == TfUnits::fraction && !in_unit(p.value))
      fail(source, where + "a fraction value must be in [0, 1]");
    if (!in_unit(p.color.x) || !in_unit(p.color.y) || !in_unit(p.color.z))
      fail(source, where + "color components must be numbers in [0, 1]");
    if (!in_unit(p.opacity)) fail(source, where + "opacity must be a number in [0, 1]");
    if (i > 0 && !(p.value > tf.points[i - 1].value))
      fail(source, where + "value " + volume_detail::number_text(p.value) +
                       (p.value == tf.points[i - 1].value ? " repeats the previous value"
                                                          : " is below the previous value") +
                       " (values must increase)");
  }
}

TransferFunction resolve(const TransferFunction& tf, const Volume& volume) {
  if (tf.units == TfUnits::data) return tf;
  TransferFunction out = tf;
  out.units = TfUnits::data;
  const double lo = volume.min_value;
  const double span = volume.max_value > volume.min_value ? volume.max_value - lo : 1.0;
  for (TfPoint& p : out.points) p.value = float(lo + span * double(p.value));
  // Rounding to float can merge two close fractions of a wide range: keep them apart.
  for (size_t i = 1; i < out.points.size(); ++i)
    if (!(out.points[i].value > out.points[i - 1].value))
      out.points[i].value = std::nextafter(out.points[i - 1].value, INFINITY);
  return out;
}

std::array<float, 4> evaluate(const TransferFunction& tf, float value) {
  const std::vector<TfPoint>& p = tf.points;
  if (p.empty()) return {0, 0, 0, 0};
  if (!(value > p.front().value)) return rgba(p.front());
  if (value >= p.back().value) return rgba(p.back());
  const size_t i = size_t(std::upper_bound(p.begin(), p.end(), value, by_value) - p.begin());
  const TfPoint& a = p[i - 1];
  const TfPoint& b = p[i];
  const float t = (value - a.value) / (b.value - a.value);
  return {a.color.x + t * (b.color.x - a.color.x), a.color.y + t * (b.color.y - a.color.y),
          a.color.z + t * (b.color.z - a.color.z), a.opacity + t * (b.opacity - a.opacity)};
}

float max_opacity(const TransferFunction& tf, float lo, float hi) {
  float m = std::max(evaluate(tf, lo)[3], evaluate(tf, hi)[3]);
  const std::vector<TfPoint>& p = tf.points;
  auto it = std::upper_bound(p.begin(), p.end(), lo, by_value);
  for (; it != p.end() && it->value < hi; ++it) m = std::max(m, it->opacity);
  return m;
}

std::array<float, 4> TransferTable::lookup(float value) const {
  if (rgba.empty()) return {0, 0, 0, 0};
  const size_t last = rgba.size() - 1;
  const float t = (value - lo) / (hi - lo) * float(last);
  if (!(t > 0)) return rgba.front();
  if (t >= float(last)) return rgba.back();
  const size_t i = std::min(size_t(t), last - 1);
  const float f = t - float(i);
  std::array<float, 4> out;
  for (int c = 0; c < 4; ++c) out[c] = rgba[i][c] + f * (rgba[i + 1][c] - rgba[i][c]);
  return out;
}

TransferTable bake(const TransferFunction& tf, float lo, float hi, int n) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || n < 2 || n > (1 << 20))
    throw std::invalid_argument("bake: lo and hi must be finite and n in 2..2^20");
  TransferTable t;
  t.lo = lo;
  t.hi = hi > lo ? hi : lo + 1;
  t.reference_step = tf.reference_step;
  t.rgba.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    const double v = double(t.lo) + (double(t.hi) - double(t.lo)) * i / (n - 1);
    t.rgba[size_t(i)] = evaluate(tf, float(v));
  }
  return t;
}

float corrected_alpha(float alpha, float step_over_reference) {
  if (!(step_over_reference > 0)) return 0;
  const float a = std::clamp(alpha, 0.0f, 1.0f);  // NaN stays NaN: caught below
  if (!(a >= 0)) return 0;
  if (step_over_reference == 1 || a == 0 || a == 1) return a;
  return float(1.0 - std::pow(1.0 - double(a), double(step_over_reference)));
}

TransferFunction load_transfer_function(const std::string& path) {
  LoadOptions options;
  options.max_total_bytes = kMaxTfFileBytes;
  const std::string text = SceneFiles(path, options).read_scene_file();
  TransferFunction tf = parse_transfer_function(text, path);
  if (tf.name.empty()) tf.name = detail::file_name(path);
  return tf;
}

}  // namespace multiray
