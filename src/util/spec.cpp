#include "util/spec.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "util/parse.h"

namespace multiray {

namespace {
bool parse_double(const std::string& s, double& out) {
  const std::optional<double> v = parse_number(s);
  if (v) out = *v;
  return v.has_value();
}
}  // namespace

Spec::Spec(const std::string& text, SpecSyntax syntax) : text_(text), syntax_(std::move(syntax)) {
  const std::vector<std::string> parts = split(text, ':');
  if (parts.empty() || parts[0].empty()) fail("missing name");
  name_ = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const size_t eq = part.find('=');
    std::string key, value;
    if (eq != std::string::npos) {
      key = part.substr(0, eq);
      value = part.substr(eq + 1);
      if (key.empty()) fail("option '" + part + "' has no key");
    } else if (i == 1 && !part.empty() && !syntax_.positional_key.empty()) {
      key = syntax_.positional_key;
      value = part;
    } else {
      fail("option '" + part + "' is not key=value");
    }
    if (!options_.emplace(key, value).second) fail("option '" + key + "' given twice");
  }
}

void Spec::fail(const std::string& what) const {
  throw std::invalid_argument(syntax_.label + " '" + text_ + "': " + what);
}

const std::string* Spec::find(const std::string& key) {
  if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.push_back(key);
  const auto it = options_.find(key);
  return it == options_.end() ? nullptr : &it->second;
}

double Spec::get_double(const std::string& key, double fallback, double lo, double hi) {
  const std::string* v = find(key);
  if (!v) return fallback;
  double x = 0;
  if (!parse_double(*v, x)) fail(key + "='" + *v + "' is not a number");
  if (x < lo || x > hi) {
    std::ostringstream range;
    range << key << "=" << *v << " is outside [" << lo << ", " << hi << "]";
    fail(range.str());
  }
  return x;
}

double Spec::get_positive(const std::string& key, double fallback, double hi) {
  const std::string* v = find(key);
  if (!v) return fallback;
  double x = 0;
  if (!parse_double(*v, x)) fail(key + "='" + *v + "' is not a number");
  if (!(x > 0 && x <= hi)) {
    std::ostringstream range;
    range << key << "=" << *v << " is outside (0, " << hi << "]";
    fail(range.str());
  }
  return x;
}

int Spec::get_int(const std::string& key, int fallback, int lo, int hi) {
  const std::string* v = find(key);
  if (!v) return fallback;
  double x = 0;
  if (!parse_double(*v, x)) fail(key + "='" + *v + "' is not a number");
  if (x != std::floor(x)) fail(key + "=" + *v + " is not an integer");
  // Only a value that fits an int is converted, and the range checked on the int.
  if (x < double(std::numeric_limits<int>::min()) || x > double(std::numeric_limits<int>::max()) ||
      int(x) < lo || int(x) > hi)
    fail(key + "=" + *v + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  return int(x);
}

bool Spec::get_bool(const std::string& key, bool fallback) {
  const std::string v =
      get_string(key, fallback ? "1" : "0", {"1", "0", "true", "false", "on", "off", "yes", "no"});
  return v == "1" || v == "true" || v == "on" || v == "yes";
}

std::string Spec::get_string(const std::string& key, const std::string& fallback,
                             const std::vector<std::string>& allowed) {
  const std::string* v = find(key);
  if (!v) return fallback;
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), *v) == allowed.end())
    fail(key + "='" + *v + "' is not one of " + join(allowed));
  return *v;
}

std::vector<double> Spec::get_ratios(const std::string& key, size_t count) {
  const std::string* v = find(key);
  if (!v) return {};
  std::vector<double> ratios;
  double sum = 0;
  for (const std::string& part : split(*v, '/')) {
    double x = 0;
    if (!parse_double(part, x) || x < 0)
      fail(key + "='" + *v + "': '" + part + "' is not a finite number >= 0");
    ratios.push_back(x);
    sum += x;
  }
  if (ratios.size() != count)
    fail(key + "='" + *v + "' has " + std::to_string(ratios.size()) + " entries for " +
         std::to_string(count) + " devices");
  if (!(sum > 0)) fail(key + "='" + *v + "' has no positive entry");
  return ratios;
}

void Spec::fail_unknown(const std::string& key, std::vector<std::string> known) const {
  std::sort(known.begin(), known.end());
  known.erase(std::unique(known.begin(), known.end()), known.end());
  fail("unknown option '" + key + "' for " + name_ +
       (known.empty() ? " (it takes none)" : " (known: " + join(known) + ")"));
}

void Spec::accept_only(const std::vector<std::string>& keys) const {
  for (const auto& [key, value] : options_)
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) fail_unknown(key, keys);
}

void Spec::finish() const {
  for (const auto& [key, value] : options_)
    if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) fail_unknown(key, asked_);
}

std::vector<std::string> split_spec_list(const std::string& text) {
  if (text.empty()) return {};
  return split(text, ',');
}

}  // namespace multiray
