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

#include "util/link.h"

namespace multiray::remote {

// The link as --link describes it (util/link.h: its grammar, shared with `simulate`).
using multiray::LinkSpec;

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
