#include "balance/efficiency.h"

#include <algorithm>
#include <cmath>

#include <cstdio>

namespace multiray::balance {

Breakdown break_down(const std::vector<DeviceTiming>& devices, double phase_ms, double host_ms) {
  Breakdown b;
  if (devices.empty() || !std::isfinite(phase_ms) || !(phase_ms > 0)) return b;
  double speed_sum = 0;
  for (const DeviceTiming& d : devices) {
    if (!std::isfinite(d.alone_ms) || !(d.alone_ms > 0)) return b;
    speed_sum += 1.0 / d.alone_ms;
  }
  b.ideal = 1.0 / speed_sum;
  double worked = 0;  // Σ a_i t_i
  for (const DeviceTiming& d : devices) {
    const double a = b.ideal / d.alone_ms;
    const double t = std::clamp(std::isfinite(d.time_ms) ? d.time_ms : 0.0, 0.0, phase_ms);
    const double stolen = std::clamp(std::isfinite(d.stolen_ms) ? d.stolen_ms : 0.0, 0.0, t);
    b.balance_loss += a * (phase_ms - t);
    b.stolen += a * stolen;
    worked += a * t;
  }
  b.overhead = worked - b.ideal - b.stolen;
  b.host = std::isfinite(host_ms) ? std::max(host_ms, 0.0) : 0.0;
  b.total = phase_ms + b.host;
  b.valid = true;
  return b;
}

Breakdown mean_breakdown(const std::vector<Breakdown>& frames) {
  Breakdown m;
  int n = 0;
  for (const Breakdown& b : frames) {
    if (!b.valid) continue;
    m.ideal += b.ideal, m.balance_loss += b.balance_loss, m.overhead += b.overhead;
    m.stolen += b.stolen, m.host += b.host, m.total += b.total;
    ++n;
  }
  if (n == 0) return Breakdown{};
  m.ideal /= n, m.balance_loss /= n, m.overhead /= n, m.stolen /= n, m.host /= n, m.total /= n;
  m.valid = true;
  return m;
}

std::string above_one_explanation(const Breakdown& b) {
  if (!(b.efficiency() > 1)) return "";
  char text[320];
  std::snprintf(text, sizeof text,
                "efficiency %.3f is above 1 because the devices' work took %.1f%% less than the "
                "ideal (%.2f of %.2f ms): they ran faster in the frame than when each was "
                "timed alone, so the ideal is too slow by at least that much",
                b.efficiency(), -100 * b.overhead / b.ideal, b.ideal + b.overhead, b.ideal);
  return text;
}

}  // namespace multiray::balance
