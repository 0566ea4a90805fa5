#include "util/parse.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace multiray {

std::optional<double> parse_number(std::string_view text) {
  // std::stod alone would skip leading blanks and stop at trailing garbage.
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  const std::string s(text);
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {  // invalid_argument, or out_of_range (1e999)
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<double> parse_size(std::string_view text) {
  static constexpr std::string_view kUnits = "KMGT";
  double scale = 1;
  if (!text.empty()) {
    const size_t unit = kUnits.find(char(std::toupper(static_cast<unsigned char>(text.back()))));
    if (unit != std::string_view::npos) {
      scale = std::pow(1024.0, double(unit + 1));
      text.remove_suffix(1);
    }
  }
  const std::optional<double> v = parse_number(text);
  if (!v || *v < 0) return std::nullopt;
  return *v * scale;
}

std::string format_bytes(uint64_t b) {
  const double bytes = double(b);
  const char* unit = "KiB";
  double value = bytes / 1024.0;
  if (b >= (1ull << 30)) {
    unit = "GiB", value = bytes / double(1ull << 30);
  } else if (b >= (1ull << 20)) {
    unit = "MiB", value = bytes / double(1ull << 20);
  }
  char out[48];
  std::snprintf(out, sizeof out, "%.1f %s", value, unit);
  return out;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, sep);) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.push_back("");
  return parts;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : sep) + p;
  return out;
}

}  // namespace multiray
