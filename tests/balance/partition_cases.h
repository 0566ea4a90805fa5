// Shared cases for the partition tests: awkward resolutions, device counts up to 64, and
// ratio vectors with zeros, a single one, random values and extreme spreads.
#pragma once

#include <random>
#include <vector>

namespace multiray::balance {

struct Size {
  int w, h;
};

// 1×1, primes, single rows and columns, and a realistic size.
inline const std::vector<Size> kSizes = {{1, 1},     {7, 1},     {1, 13},  {2, 3},
                                         {641, 359}, {640, 360}, {97, 61}, {256, 1}};
inline const std::vector<int> kDeviceCounts = {1, 2, 3, 5, 16, 64};

inline std::vector<double> random_ratios(std::mt19937_64& rng, int devices) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> r(static_cast<size_t>(devices));
  for (double& x : r) x = u(rng) < 0.2 ? 0.0 : u(rng);
  return r;
}

inline std::vector<std::vector<double>> ratio_cases(std::mt19937_64& rng, int devices) {
  std::vector<std::vector<double>> cases;
  cases.push_back(std::vector<double>(size_t(devices), 1.0));  // even
  std::vector<double> one(size_t(devices), 0.0);
  one.back() = 1.0;  // everything to the last device, zeros elsewhere
  cases.push_back(one);
  std::vector<double> skew(static_cast<size_t>(devices));
  for (int i = 0; i < devices; ++i) skew[size_t(i)] = i % 2 ? 1e-6 : 3.0;
  cases.push_back(skew);
  for (int k = 0; k < 3; ++k) cases.push_back(random_ratios(rng, devices));
  return cases;
}

}  // namespace multiray::balance
