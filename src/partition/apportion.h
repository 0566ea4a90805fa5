// Integer shares from real ratios: the rounding every partition shares.
#pragma once

#include <cstdint>
#include <vector>

namespace multiray::balance {

// Splits `total` units (rows, strips, pixels) among devices in proportion to `ratios`
// by largest-remainder (Hamilton) rounding: the counts sum to exactly `total`, each count
// is within 1 of its exact quota, and a ratio of 0 always gets 0. Ties in the remainder go
// to the lower index, so the result is deterministic.
//
// Negative, NaN and infinite ratios count as 0. If no ratio is positive the units are
// split evenly over all devices (so a caller never loses pixels by passing zeros).
// `total` < 0 is treated as 0.
std::vector<int64_t> apportion(const std::vector<double>& ratios, int64_t total);

// The ratios after the sanitising `apportion` applies, normalised to sum to 1 (even split
// when none is positive; empty for an empty input).
std::vector<double> normalized_ratios(const std::vector<double>& ratios);

}  // namespace multiray::balance
