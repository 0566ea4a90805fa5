#include "partition/apportion.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

namespace multiray::balance {

std::vector<double> normalized_ratios(const std::vector<double>& ratios) {
  std::vector<double> out(ratios.size(), 0.0);
  double sum = 0;
  for (size_t i = 0; i < ratios.size(); ++i) {
    const double r = ratios[i];
    if (std::isfinite(r) && r > 0) out[i] = r;
    sum += out[i];
  }
  if (out.empty()) return out;
  if (!(sum > 0) || !std::isfinite(sum)) {
    std::fill(out.begin(), out.end(), 1.0 / double(out.size()));
    return out;
  }
  for (double& r : out) r /= sum;
  return out;
}

std::vector<int64_t> apportion(const std::vector<double>& ratios, int64_t total) {
  const size_t n = ratios.size();
  std::vector<int64_t> counts(n, 0);
  if (n == 0 || total <= 0) return counts;
  const std::vector<double> w = normalized_ratios(ratios);

  // Quotas in long double: total can be 2^31 pixels and w a few ulps off 1.
  std::vector<long double> frac(n, 0.0L);
  int64_t assigned = 0;
  for (size_t i = 0; i < n; ++i) {
    const long double quota = (long double)total * (long double)w[i];
    const long double whole = std::floor(quota);
    counts[i] = std::min<int64_t>(int64_t(whole), total);
    frac[i] = quota - whole;
    assigned += counts[i];
  }
  // Rounding can leave the floors a unit above total; take it back from the largest.
  while (assigned > total) {
    const size_t big = size_t(std::max_element(counts.begin(), counts.end()) - counts.begin());
    --counts[big];
    --assigned;
  }
  // Hand out the remaining units by largest remainder, only to devices with a positive
  // ratio (a ratio of 0 must stay empty).
  std::vector<size_t> order;
  for (size_t i = 0; i < n; ++i)
    if (w[i] > 0) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return frac[a] > frac[b]; });
  for (size_t k = 0; assigned < total && !order.empty(); k = (k + 1) % order.size()) {
    ++counts[order[k]];
    ++assigned;
  }
  return counts;
}

}  // namespace multiray::balance
