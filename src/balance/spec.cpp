#include "balance/spec.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>

namespace multiray::balance {

namespace {
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.push_back("");
  return parts;
}

bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  size_t used = 0;
  try {
    out = std::stod(s, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == s.size() && std::isfinite(out);
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}
}  // namespace

Spec::Spec(const std::string& text) : text_(text) {
  const std::vector<std::string> parts = split(text, ':');
  if (parts.empty() || parts[0].empty()) fail("missing balancer name");
  name_ = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) {
    const size_t eq = parts[i].find('=');
    if (eq == std::string::npos) fail("option '" + parts[i] + "' is not key=value");
    const std::string key = parts[i].substr(0, eq);
    if (key.empty()) fail("option '" + parts[i] + "' has no key");
    if (!options_.emplace(key, parts[i].substr(eq + 1)).second)
      fail("option '" + key + "' given twice");
  }
}

void Spec::fail(const std::string& what) const {
  throw std::invalid_argument("balancer spec '" + text_ + "': " + what);
}

double Spec::get_double(const std::string& key, double fallback, double lo, double hi) {
  asked_.push_back(key);
  const auto it = options_.find(key);
  if (it == options_.end()) return fallback;
  double v = 0;
  if (!parse_double(it->second, v)) fail(key + "='" + it->second + "' is not a number");
  if (v < lo || v > hi) {
    std::ostringstream range;
    range << key << "=" << it->second << " is outside [" << lo << ", " << hi << "]";
    fail(range.str());
  }
  return v;
}

int Spec::get_int(const std::string& key, int fallback, int lo, int hi) {
  const double v = get_double(key, fallback, lo, hi);
  if (v != std::floor(v)) fail(key + "=" + options_.at(key) + " is not an integer");
  return int(v);
}

bool Spec::get_bool(const std::string& key, bool fallback) {
  const std::string v =
      get_string(key, fallback ? "1" : "0", {"1", "0", "true", "false", "on", "off", "yes", "no"});
  return v == "1" || v == "true" || v == "on" || v == "yes";
}

std::string Spec::get_string(const std::string& key, const std::string& fallback,
                             const std::vector<std::string>& allowed) {
  asked_.push_back(key);
  const auto it = options_.find(key);
  if (it == options_.end()) return fallback;
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), it->second) == allowed.end())
    fail(key + "='" + it->second + "' is not one of " + join(allowed));
  return it->second;
}

std::vector<double> Spec::get_ratios(const std::string& key, size_t count) {
  asked_.push_back(key);
  const auto it = options_.find(key);
  if (it == options_.end()) return {};
  std::vector<double> ratios;
  double sum = 0;
  for (const std::string& part : split(it->second, '/')) {
    double v = 0;
    if (!parse_double(part, v) || v < 0)
      fail(key + "='" + it->second + "': '" + part + "' is not a finite number >= 0");
    ratios.push_back(v);
    sum += v;
  }
  if (ratios.size() != count)
    fail(key + "='" + it->second + "' has " + std::to_string(ratios.size()) + " entries for " +
         std::to_string(count) + " devices");
  if (!(sum > 0)) fail(key + "='" + it->second + "' has no positive entry");
  return ratios;
}

void Spec::finish() const {
  for (const auto& [key, value] : options_)
    if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) {
      std::vector<std::string> known = asked_;
      std::sort(known.begin(), known.end());
      known.erase(std::unique(known.begin(), known.end()), known.end());
      fail("unknown option '" + key + "' for " + name_ +
           (known.empty() ? " (it takes none)" : " (known: " + join(known) + ")"));
    }
}

}  // namespace multiray::balance
