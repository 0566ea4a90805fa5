// Parsing of specs "name:key=value:key=value", as balancers (`--balancer dlb:interval=3`)
// and devices (`--devices opencl:1:wg=32`) are written. Values are read by typed getters
// that check ranges; finish() then rejects any option nobody asked for, so a typo is an
// error instead of a silently ignored setting. Lists of specs are "spec,spec,...".
//
//   Spec spec("queue:tile=32");
//   const int tile = spec.get_int("tile", 64, 1, 4096);  // 32
//   spec.finish();                                       // no other option was given
#pragma once

#include <map>
#include <string>
#include <vector>

namespace multiray {

// How a kind of spec is read and named in error messages.
struct SpecSyntax {
  // Every error reads "<label> '<text>': <what>".
  std::string label = "balancer spec";
  // When not empty, a bare value right after the name ("opencl:1") is the option with this
  // key (as "opencl:index=1"). Otherwise such a value is an error.
  std::string positional_key;
};

class Spec {
 public:
  // Throws std::invalid_argument for an empty name, an option without '=' (but for the
  // positional value `syntax` allows), an empty key or a key given twice.
  explicit Spec(const std::string& text, SpecSyntax syntax = {});

  const std::string& text() const { return text_; }
  const std::string& name() const { return name_; }
  // Every option as written, key -> value (the positional value under its key).
  const std::map<std::string, std::string>& options() const { return options_; }
  bool has(const std::string& key) const { return options_.count(key) != 0; }
  // The keys the getters asked for so far (given or not), in order, without repeats.
  const std::vector<std::string>& asked() const { return asked_; }

  // Each getter returns the option's value, or `fallback` (unchecked) when it is absent,
  // and throws std::invalid_argument when the value does not parse or is out of range.
  // Numbers must be finite and fill the whole value ("2x", "nan" and " 2" are errors).
  double get_double(const std::string& key, double fallback, double lo, double hi);  // [lo, hi]
  double get_positive(const std::string& key, double fallback, double hi);           // (0, hi]
  // A whole number (also written "2.0" or "1e3") that fits an int and lies in [lo, hi].
  int get_int(const std::string& key, int fallback, int lo, int hi);
  bool get_bool(const std::string& key, bool fallback);  // 1/0, true/false, on/off, yes/no
  // Any value when `allowed` is empty, else one of `allowed`.
  std::string get_string(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed);
  // A '/'-separated list of non-negative finite numbers ("3/1"); `count` entries expected.
  std::vector<double> get_ratios(const std::string& key, size_t count);

  // Throws std::invalid_argument naming the first option not in `keys` and listing `keys`;
  // for specs whose whole set of options is known before any is read.
  void accept_only(const std::vector<std::string>& keys) const;
  // Throws std::invalid_argument naming the first option no getter asked for and listing
  // the ones asked for.
  void finish() const;

  // "<label> 'text': <what>" as the std::invalid_argument every error uses.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  // The value of `key` (marked as asked for), or nullptr when it is absent.
  const std::string* find(const std::string& key);
  [[noreturn]] void fail_unknown(const std::string& key, std::vector<std::string> known) const;

  std::string text_, name_;
  SpecSyntax syntax_;
  std::map<std::string, std::string> options_;
  std::vector<std::string> asked_;
};

// Splits a list "spec,spec,..." at every comma (no quoting or escaping: specs contain no
// commas). An empty `text` gives no items; empty items are kept, so "a,,b" has three and
// the empty one fails as a spec without a name instead of being silently skipped.
std::vector<std::string> split_spec_list(const std::string& text);

}  // namespace multiray
