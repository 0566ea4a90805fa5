#include "distributed/link.h"

#include <algorithm>
#include <cmath>

namespace multiray::remote {

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
