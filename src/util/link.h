// An emulated network link between the master and its workers, as --link writes it for
// `render --distributed` and `simulate` alike: none, lan, wifi, or LATENCY_MS,MBIT[,separate].
// Always labelled emulated where it is reported. Standard library only.
#pragma once

#include <string>

namespace multiray {

struct LinkSpec {
  std::string name = "none";  // preset name or "custom"
  double latency_ms = 0;      // one way, per message
  double mbit_per_s = 0;      // 0: unlimited
  bool shared = true;         // one link at the master for every worker
  bool active() const { return latency_ms > 0 || mbit_per_s > 0; }
  // "emulated LAN (0.1 ms, 10000 Mbit/s, shared master link)" or "none (real transport)".
  std::string describe() const;
};

// none; lan (0.1 ms, 10 Gbit/s); wifi (5 ms, 200 Mbit/s: our assumption of a shared
// 802.11 link such as a mobile cluster's, not a figure of Seo et al., who give none); or
// LATENCY_MS,MBIT[,separate]: latency in [0, 10000] ms, bandwidth in [0, 1e6]
// Mbit/s (0: unlimited), `separate` for one link per worker instead of the shared master
// link. Throws std::invalid_argument "'TEXT': why (expected ...)".
LinkSpec parse_link(const std::string& text);

}  // namespace multiray
