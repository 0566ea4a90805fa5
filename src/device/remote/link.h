// Emulated network links (always labelled emulated in output and docs). This kernel has
// no `tc netem`, so latency and bandwidth are emulated in user space by the master's
// transport: every message to or from a worker is held until the emulated link would
// have delivered it. As in Seo et al. 2022 (Fig. 6), the master's link is shared by all
// workers by default: messages cross it one at a time, in both directions (a Wi-Fi
// medium is half-duplex). Heartbeats are not charged.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace multiray::remote {

struct LinkSpec {
  std::string name = "none";  // preset name or "custom"
  double latency_ms = 0;      // one way, per message
  double mbit_per_s = 0;      // 0: unlimited
  bool shared = true;         // one link at the master for every worker
  bool active() const { return latency_ms > 0 || mbit_per_s > 0; }
  // "emulated LAN (0.1 ms, 10000 Mbit/s, shared master link)" or "none (real transport)".
  std::string describe() const;
};

// --link: none, lan (0.1 ms, 10 Gbit/s), wifi (5 ms, 200 Mbit/s: a mobile Wi-Fi cluster,
// Seo et al.), or LATENCY_MS,MBIT[,separate] (separate: one link per worker instead of
// the shared master link). Throws InputError with a one-line message.
LinkSpec parse_link(const std::string& text);

// The emulated link's clock: when a message entering it now is delivered.
class LinkModel {
 public:
  using Clock = std::chrono::steady_clock;
  LinkModel(LinkSpec spec, int peers) : spec_(std::move(spec)), free_at_(size_t(peers)) {}
  // Delivery time of `bytes` bytes to or from `peer` (0-based), entering the link at
  // `now`: after the messages already on the same link, plus the latency.
  Clock::time_point deliver_at(int peer, size_t bytes, Clock::time_point now);
  const LinkSpec& spec() const { return spec_; }

 private:
  LinkSpec spec_;
  std::vector<Clock::time_point> free_at_;  // per link: when it is next free
};

}  // namespace multiray::remote
