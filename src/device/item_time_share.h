// How a device whose threads render several items at once charges its time to them.
// Balancers read ItemReport::time_ms as what an item cost the device (util/rect.h): the
// items' times of a frame must add up to the device's busy time, as they do when the
// device renders one item after another. With items in progress on several threads at
// once, an item's own wall time would count the same wall time once per thread; so each
// stretch of wall time is split evenly among the items in progress during it: while n
// items run together each is charged 1/n of the elapsed time.
#pragma once

#include <mutex>

#include "core/clock.h"

namespace multiray {

class ItemTimeShare {
 public:
  // An item starts; returns the mark to give finish(). Thread-safe.
  double start() {
    std::lock_guard<std::mutex> lock(mutex_);
    advance();
    ++running_;
    return per_item_ms_;
  }
  // The item started at `mark` ends; returns its share of the device's time in ms.
  // Every start() needs its finish(), also for an item that failed. Thread-safe.
  double finish(double mark) {
    std::lock_guard<std::mutex> lock(mutex_);
    advance();
    --running_;
    return per_item_ms_ - mark;
  }

 private:
  // Requires mutex_ held. Charges the time since the last change to the running items.
  void advance() {
    const SteadyClock::time_point now = SteadyClock::now();
    if (running_ > 0) per_item_ms_ += ms_between(last_, now) / running_;
    last_ = now;
  }

  std::mutex mutex_;
  SteadyClock::time_point last_ = SteadyClock::now();
  int running_ = 0;         // items in progress
  double per_item_ms_ = 0;  // time charged so far to an item running all along
};

}  // namespace multiray
