#include "util/link.h"

#include <sstream>
#include <stdexcept>

#include "util/parse.h"

namespace multiray {

std::string LinkSpec::describe() const {
  if (!active()) return "none (real transport)";
  std::ostringstream out;
  out << "emulated " << name << " (" << latency_ms << " ms, ";
  if (mbit_per_s > 0)
    out << mbit_per_s;
  else
    out << "unlimited";
  out << " Mbit/s, " << (shared ? "shared master link" : "one link per worker") << ")";
  return out.str();
}

LinkSpec parse_link(const std::string& text) {
  if (text == "none") return LinkSpec{};
  if (text == "lan") return LinkSpec{"LAN", 0.1, 10000, true};
  if (text == "wifi") return LinkSpec{"mobile Wi-Fi", 5.0, 200, true};
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("'" + text + "': " + why +
                                 " (expected none, lan, wifi or LATENCY_MS,MBIT[,separate])");
  };
  const std::vector<std::string> parts = split(text, ',');
  if (parts.size() < 2 || parts.size() > 3) throw bad("not a link");
  LinkSpec s{"custom", 0, 0, true};
  double* values[2] = {&s.latency_ms, &s.mbit_per_s};
  for (size_t i = 0; i < 2; ++i) {
    const auto v = parse_number(parts[i]);
    if (!v) throw bad("'" + parts[i] + "' is not a number");
    *values[i] = *v;
  }
  if (s.latency_ms < 0 || s.latency_ms > 10000) throw bad("latency must be in [0, 10000] ms");
  if (s.mbit_per_s < 0 || s.mbit_per_s > 1e6) throw bad("bandwidth must be in [0, 1e6] Mbit/s");
  if (parts.size() == 3) {
    if (parts[2] != "separate") throw bad("'" + parts[2] + "' is not 'separate'");
    s.shared = false;
  }
  return s;
}

}  // namespace multiray
