// How the master keeps a worker supplied with items pulled on demand (remote_device.h):
// plain state, updated as messages go and come, that says whether one more item may be
// sent now. Two forms:
//
//  - the paper's (Seo, Park & Ihm 2022, strategy I; balance::Plan::pull_on_ready): one
//    item index outstanding at a time. The next is sent only when the worker reports the
//    last one rendered (Ready, protocol.h); its result may still be uploading, so the
//    upload overlaps rendering the next item, but every item waits for a round trip;
//  - ours ("deep"): up to `depth` Work messages whose results are not all back, so the
//    worker finds its next item waiting and the round trip hides (--depth).
#pragma once

#include <algorithm>

namespace multiray::remote {

struct DemandPipeline {
  bool on_ready = false;  // the paper's form
  int depth = 2;          // ours: Work messages in flight, >= 1
  int units = 0;          // Work messages whose results have not all come back
  int unready = 0;        // the paper's form: items sent, not yet reported rendered

  // May one more item on demand be sent now?
  bool may_send() const { return on_ready ? unready == 0 : units < std::max(1, depth); }
  // A Work message left: `on_demand` for a pulled item, false for the batch of the
  // device's own items (which reports no readiness).
  void sent(bool on_demand) {
    ++units;
    if (on_ready && on_demand) ++unready;
  }
  // The worker reported an item rendered (the paper's form only).
  void ready() { unready = std::max(0, unready - 1); }
  // A Work message's results all came back.
  void result() { units = std::max(0, units - 1); }
};

}  // namespace multiray::remote
