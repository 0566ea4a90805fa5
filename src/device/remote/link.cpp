#include "device/remote/link.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/error.h"

namespace multiray::remote {

std::string LinkSpec::describe() const {
  if (!active()) return "none (real transport)";
  return fmt::format("emulated {} ({} ms, {} Mbit/s, {})", name, latency_ms,
                     mbit_per_s > 0 ? fmt::format("{}", mbit_per_s) : "unlimited",
                     shared ? "shared master link" : "one link per worker");
}

LinkSpec parse_link(const std::string& text) {
  if (text == "none") return LinkSpec{};
  if (text == "lan") return LinkSpec{"LAN", 0.1, 10000, true};
  if (text == "wifi") return LinkSpec{"mobile Wi-Fi", 5.0, 200, true};
  const auto bad = [&](const std::string& why) {
    return InputError("--link '" + text + "': " + why +
                      " (expected none, lan, wifi or LATENCY_MS,MBIT[,separate])");
  };
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t comma; (comma = text.find(',', start)) != std::string::npos; start = comma + 1)
    parts.push_back(text.substr(start, comma - start));
  parts.push_back(text.substr(start));
  if (parts.size() < 2 || parts.size() > 3) throw bad("not a link");
  LinkSpec s{"custom", 0, 0, true};
  double* values[2] = {&s.latency_ms, &s.mbit_per_s};
  for (int i = 0; i < 2; ++i) {
    size_t used = 0;
    try {
      *values[i] = std::stod(parts[size_t(i)], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != parts[size_t(i)].size() || !std::isfinite(*values[i]))
      throw bad("'" + parts[size_t(i)] + "' is not a number");
  }
  if (s.latency_ms < 0 || s.latency_ms > 10000) throw bad("latency must be in [0, 10000] ms");
  if (s.mbit_per_s < 0 || s.mbit_per_s > 1e6) throw bad("bandwidth must be in [0, 1e6] Mbit/s");
  if (parts.size() == 3) {
    if (parts[2] != "separate") throw bad("'" + parts[2] + "' is not 'separate'");
    s.shared = false;
  }
  return s;
}

LinkModel::Clock::time_point LinkModel::deliver_at(int peer, size_t bytes, Clock::time_point now) {
  if (!spec_.active()) return now;
  Clock::time_point& free = free_at_.at(spec_.shared ? 0 : size_t(peer));
  const double transfer_s =
      spec_.mbit_per_s > 0 ? double(bytes) * 8.0 / (spec_.mbit_per_s * 1e6) : 0;
  const auto start = std::max(now, free);
  free = start +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(transfer_s));
  return free + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double, std::milli>(spec_.latency_ms));
}

}  // namespace multiray::remote
