// Helpers for balancer tests on the simulator: device models, cost models with uneven
// pixel cost, and per-frame summaries of a run.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "balance/balancer.h"
#include "balance/simulate.h"

namespace multiray::balance::testing {

inline std::vector<SimDevice> devices_with_speeds(const std::vector<double>& speeds,
                                                  double frame_noise = 0) {
  std::vector<SimDevice> d(speeds.size());
  for (size_t i = 0; i < d.size(); ++i) {
    d[i].speed = speeds[i];
    d[i].frame_noise = frame_noise;
  }
  return d;
}

// Speeds that change at frame `at` (between frames, like the engine's --perturb).
inline std::function<std::vector<SimDevice>(int)> speed_step(std::vector<double> before,
                                                             std::vector<double> after, int at,
                                                             double noise = 0) {
  return [=](int frame) { return devices_with_speeds(frame < at ? before : after, noise); };
}

inline std::function<std::vector<SimDevice>(int)> constant(std::vector<double> speeds,
                                                           double noise = 0) {
  return speed_step(speeds, speeds, 0, noise);
}

// 1 µs per sample everywhere.
inline CostFn flat_cost(const FrameShape& shape) { return uniform_cost(shape, 1e-3); }

// Uneven cost, like a scene whose bottom holds the detail: rows in the lower third cost
// 6× the upper rows, plus a smooth ripple along x.
inline CostFn uneven_cost(const FrameShape& shape) {
  return pixel_cost(shape, [h = shape.height, w = shape.width](int, int x, int y) {
    const double row = y * 3 >= 2 * h ? 6.0 : 1.0;
    return 1e-3 * row * (1.0 + 0.5 * std::sin(6.28 * x / std::max(w, 1)));
  });
}

// The share of the work of device `i` in the plan (plan.ratios).
inline double planned(const SimFrame& f, int i) { return f.plan.ratios[size_t(i)]; }

// Mean imbalance over frames [from, to).
inline double mean_imbalance(const std::vector<SimFrame>& run, int from, int to) {
  double s = 0;
  for (int f = from; f < to; ++f) s += imbalance(run[size_t(f)].stats);
  return s / (to - from);
}

// First frame at or after `from` from which on imbalance stays below `limit`; -1 if never
// (balance::recovered_from, the bench's definition of recovery).
inline int settles_at(const std::vector<SimFrame>& run, int from, double limit) {
  std::vector<double> lambda;
  for (const SimFrame& f : run) lambda.push_back(imbalance(f.stats));
  return recovered_from(lambda, from, limit);
}

// Direction flips of device `i`'s planned share over frames [from, to): frames f in
// [from + 2, to) where the share moved one way into frame f - 1 and the other way into f.
// Moves under 1e-4 of the frame count as none (a balancer holding its shares).
inline int direction_flips(const std::vector<SimFrame>& run, int i, int from, int to) {
  int flips = 0;
  for (int f = from + 2; f < to; ++f) {
    const double d0 = planned(run[size_t(f - 1)], i) - planned(run[size_t(f - 2)], i);
    const double d1 = planned(run[size_t(f)], i) - planned(run[size_t(f - 1)], i);
    flips += std::abs(d0) > 1e-4 && std::abs(d1) > 1e-4 && (d0 > 0) != (d1 > 0) ? 1 : 0;
  }
  return flips;
}

inline double stddev_of_share(const std::vector<SimFrame>& run, int device, int from, int to) {
  double m = 0, m2 = 0;
  for (int f = from; f < to; ++f) m += planned(run[size_t(f)], device);
  m /= (to - from);
  for (int f = from; f < to; ++f) m2 += std::pow(planned(run[size_t(f)], device) - m, 2);
  return std::sqrt(m2 / (to - from));
}

}  // namespace multiray::balance::testing
