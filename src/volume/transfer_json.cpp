// The JSON form of a transfer function (format in transfer_function.h and
// docs/volumes.md). Every number is checked after conversion to float.
#include <cfloat>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/scene_files.h"
#include "volume/transfer_function.h"

namespace multiray {

using detail::fail;
using nlohmann::json;

namespace {

// `j` as a float, or a problem: not a number, or beyond float's finite range.
bool to_float(const json& j, float* out) {
  if (!j.is_number()) return false;
  const double d = j.get<double>();
  if (!std::isfinite(d) || std::fabs(d) > double(FLT_MAX)) return false;
  *out = float(d);
  return true;
}

// Throws unless every key of object `j` is in `allowed`.
void check_keys(const json& j, std::initializer_list<const char*> allowed,
                const std::string& source, const std::string& where) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : allowed) known = known || it.key() == k;
    if (!known) fail(source, where + "unknown key '" + it.key() + "'");
  }
}

TfPoint parse_point(const json& j, const std::string& source, size_t i) {
  const std::string where = "point " + std::to_string(i) + ": ";
  if (!j.is_object())
    fail(source, where + "must be an object {\"value\", \"color\", \"opacity\"}");
  check_keys(j, {"value", "color", "opacity"}, source, where);
  for (const char* k : {"value", "color", "opacity"})
    if (!j.contains(k)) fail(source, where + "\"" + k + "\" is missing");
  TfPoint p;
  if (!to_float(j["value"], &p.value)) fail(source, where + "value must be a finite number");
  const json& c = j["color"];
  if (!c.is_array() || c.size() != 3 || !to_float(c[0], &p.color.x) ||
      !to_float(c[1], &p.color.y) || !to_float(c[2], &p.color.z))
    fail(source, where + "color must be an array of three numbers in [0, 1]");
  if (!to_float(j["opacity"], &p.opacity))
    fail(source, where + "opacity must be a number in [0, 1]");
  return p;
}

}  // namespace

TransferFunction parse_transfer_function(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    fail(source, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) fail(source, "a transfer function must be a JSON object");
  check_keys(j, {"name", "units", "reference_step", "points"}, source, "");
  TransferFunction tf;
  if (j.contains("name")) {
    if (!j["name"].is_string()) fail(source, "name must be a string");
    tf.name = j["name"].get<std::string>();
  }
  if (j.contains("units")) {
    const json& u = j["units"];
    if (u == "data")
      tf.units = TfUnits::data;
    else if (u == "fraction")
      tf.units = TfUnits::fraction;
    else
      fail(source, "units must be \"data\" or \"fraction\"");
  }
  if (j.contains("reference_step") && !to_float(j["reference_step"], &tf.reference_step))
    fail(source, "reference_step must be a number in (0, 1000]");
  if (!j.contains("points") || !j["points"].is_array())
    fail(source, "\"points\" must be an array of at least 2 points");
  const json& points = j["points"];
  if (points.size() > kMaxTfPoints)
    fail(source, "more than " + std::to_string(kMaxTfPoints) + " points");
  for (size_t i = 0; i < points.size(); ++i)
    tf.points.push_back(parse_point(points[i], source, i));
  check_transfer_function(tf, source);
  return tf;
}

}  // namespace multiray
