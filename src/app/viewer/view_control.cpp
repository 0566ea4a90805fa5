#include "app/viewer/view_control.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace multiray::app::viewer {

namespace {
constexpr size_t kMaxMessage = 4096;

double number(const nlohmann::json& j, const char* key, double lo, double hi) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number())
    throw InputError(std::string("'") + key + "' must be a number");
  const double v = it->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(std::string("'") + key + "' is out of range");
  return v;
}
}  // namespace

Command parse_command(const std::string& text, int views) {
  if (text.size() > kMaxMessage) throw InputError("message longer than 4096 bytes");
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw InputError("not a JSON object");
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) throw InputError("'type' must be a string");
  const std::string t = type->get<std::string>();
  Command c;
  if (t == "orbit") {
    c.kind = Command::Kind::Orbit;
    c.x = float(number(j, "dx", -360, 360)), c.y = float(number(j, "dy", -360, 360));
  } else if (t == "pan") {
    c.kind = Command::Kind::Pan;
    c.x = float(number(j, "dx", -10, 10)), c.y = float(number(j, "dy", -10, 10));
  } else if (t == "zoom") {
    c.kind = Command::Kind::Zoom;
    c.x = float(number(j, "factor", 0.1, 10));
  } else if (t == "reset") {
    c.kind = Command::Kind::Reset;
  } else if (t == "balancer") {
    c.kind = Command::Kind::Balancer;
    const auto spec = j.find("spec");
    if (spec == j.end() || !spec->is_string() || spec->get<std::string>().empty() ||
        spec->get<std::string>().size() > 256)
      throw InputError("'spec' must be a balancer spec");
    c.spec = spec->get<std::string>();
  } else if (t == "view") {
    c.kind = Command::Kind::View;
    c.view = int(number(j, "index", 0, std::max(0, views - 1)));
  } else if (t == "tf") {
    c.kind = Command::Kind::Tf;
    const auto preset = j.find("preset"), text = j.find("json");
    if (preset != j.end() && preset->is_string() && !preset->get<std::string>().empty() &&
        preset->get<std::string>().size() <= 64)
      c.spec = preset->get<std::string>();
    else if (text != j.end() && text->is_string() && !text->get<std::string>().empty())
      c.json = text->get<std::string>();
    else
      throw InputError("'tf' needs a 'preset' name or 'json' text");
  } else if (t == "look") {
    c.kind = Command::Kind::Look;
    c.x = float(number(j, "yaw", -360, 360)), c.y = float(number(j, "pitch", -180, 180));
  } else if (t == "denoise") {
    c.kind = Command::Kind::Denoise;
    const auto method = j.find("method");
    if (method == j.end() || !method->is_string() ||
        !parse_denoise(method->get<std::string>(), c.denoise))
      throw InputError("'method' must be none, atrous, svgf or auto");
  } else if (t == "target") {
    c.kind = Command::Kind::Target;
    c.x = float(number(j, "ms", 1, 100000));
  } else {
    throw InputError("unknown message type '" + t.substr(0, 32) + "'");
  }
  return c;
}

}  // namespace multiray::app::viewer
