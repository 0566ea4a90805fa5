// Parsing of balancer specs "name:key=value:key=value". Values are read by typed getters
// that check ranges; finish() then rejects any option nobody asked for, so a typo is an
// error instead of a silently ignored setting.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace multiray::balance {

class Spec {
 public:
  // Throws std::invalid_argument for an empty name, an option without '=', an empty key
  // or a key given twice.
  explicit Spec(const std::string& text);

  const std::string& name() const { return name_; }

  // Each getter returns the option's value, or `fallback` when it is absent, and throws
  // std::invalid_argument when the value does not parse or is outside [lo, hi].
  double get_double(const std::string& key, double fallback, double lo, double hi);
  int get_int(const std::string& key, int fallback, int lo, int hi);
  bool get_bool(const std::string& key, bool fallback);  // 1/0, true/false, on/off
  std::string get_string(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed);
  // A '/'-separated list of non-negative finite numbers ("3/1"); `count` entries expected.
  std::vector<double> get_ratios(const std::string& key, size_t count);
  bool has(const std::string& key) const { return options_.count(key) != 0; }

  // Throws std::invalid_argument naming the first option no getter asked for.
  void finish() const;

  // "balancer spec 'text': <what>" as the std::invalid_argument every error uses.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string text_, name_;
  std::map<std::string, std::string> options_;
  std::vector<std::string> asked_;
};

}  // namespace multiray::balance
