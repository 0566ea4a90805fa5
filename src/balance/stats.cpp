#include "balance/stats.h"

#include <algorithm>
#include <cmath>

namespace multiray::balance {

namespace {
bool usable_time(double ms) { return std::isfinite(ms) && ms >= 0; }
std::vector<double> usable_times(const FrameStats& stats) {
  std::vector<double> t;
  for (const DeviceFrameStats& d : stats.devices)
    if (d.alive && !d.rested && usable_time(d.time_ms)) t.push_back(d.time_ms);
  return t;
}
std::vector<double> usable_times(const std::vector<double>& times) {
  std::vector<double> t;
  for (double ms : times)
    if (usable_time(ms)) t.push_back(ms);
  return t;
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / double(v.size());
}
}  // namespace

double frame_time_ms(const FrameStats& stats) {
  const std::vector<double> t = usable_times(stats);
  return t.empty() ? 0 : *std::max_element(t.begin(), t.end());
}

double imbalance(const FrameStats& stats) { return imbalance(usable_times(stats)); }

double deviation(const FrameStats& stats) { return deviation(usable_times(stats)); }

double imbalance(const std::vector<double>& times) {
  const std::vector<double> t = usable_times(times);
  const double m = mean(t);
  if (t.empty() || !(m > 0)) return 0;
  return *std::max_element(t.begin(), t.end()) / m - 1;
}

double deviation(const std::vector<double>& times) {
  const std::vector<double> t = usable_times(times);
  const double m = mean(t);
  if (t.empty() || !(m > 0)) return 0;
  double worst = 0;
  for (double x : t) worst = std::max(worst, std::abs(x - m));
  return worst / m;
}

int recovered_from(const std::vector<double>& imbalance, int from, double limit) {
  if (from < 0 || from >= int(imbalance.size())) return -1;
  int f = int(imbalance.size());
  while (f > from && imbalance[size_t(f - 1)] < limit) --f;
  return f == int(imbalance.size()) ? -1 : f;
}

}  // namespace multiray::balance
