#include "balance/targeting.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace multiray::balance {

AdaptMode parse_adapt_mode(const std::string& text) {
  if (text == "none") return AdaptMode::none;
  if (text == "last-frame") return AdaptMode::last_frame;
  if (text == "predict") return AdaptMode::predict;
  if (text == "two-pass") return AdaptMode::two_pass;
  throw std::invalid_argument("adaptation mode '" + text +
                              "' must be none, last-frame, predict or two-pass");
}

AdaptSpace parse_adapt_space(const std::string& text) {
  if (text == "ray") return AdaptSpace::ray;
  if (text == "image") return AdaptSpace::image;
  if (text == "hybrid") return AdaptSpace::hybrid;
  throw std::invalid_argument("adaptation space '" + text + "' must be ray, image or hybrid");
}

const char* adapt_mode_name(AdaptMode m) {
  switch (m) {
    case AdaptMode::none:
      return "none";
    case AdaptMode::last_frame:
      return "last-frame";
    case AdaptMode::predict:
      return "predict";
    case AdaptMode::two_pass:
      return "two-pass";
  }
  return "?";
}

const char* adapt_space_name(AdaptSpace s) {
  return s == AdaptSpace::ray ? "ray" : s == AdaptSpace::image ? "image" : "hybrid";
}

Quality quality_of(double cost, AdaptSpace space) {
  Quality q;
  if (space == AdaptSpace::ray) q.step_scale = 1 / cost;
  if (space == AdaptSpace::image) q.image_scale = std::sqrt(cost);
  if (space == AdaptSpace::hybrid)
    q.image_scale = std::pow(cost, 0.25), q.step_scale = 1 / std::sqrt(cost);
  return q;
}

FrameTimeTargeting::FrameTimeTargeting(const TargetingConfig& config) : config_(config) {
  if (!(std::isfinite(config.target_ms) && config.target_ms > 0))
    throw std::invalid_argument("the target frame time must be a finite number of ms > 0");
  if (!(config.min_cost > 0 && config.min_cost <= 1))
    throw std::invalid_argument("the lowest cost factor must be in (0, 1]");
  if (!(config.max_raise > 0 && config.max_raise <= 1))
    throw std::invalid_argument("the quality raise limit must be in (0, 1]");
  if (!(config.probe_cost >= config.min_cost && config.probe_cost <= 1))
    throw std::invalid_argument("the first pass's cost factor must be in [lowest, 1]");
}

double FrameTimeTargeting::clamp_next(double wanted) const {
  if (!std::isfinite(wanted)) return cost_;
  const double ceiling = std::min(1.0, cost_ / config_.max_raise);
  return std::clamp(wanted, config_.min_cost, ceiling);
}

double FrameTimeTargeting::next(const std::function<double(double)>& predict_ms) {
  const double target = config_.target_ms;
  switch (config_.mode) {
    case AdaptMode::none:
      cost_ = 1;
      break;
    case AdaptMode::two_pass:
      cost_ = config_.probe_cost;
      break;
    case AdaptMode::last_frame:
      if (last_ms_ > 0) cost_ = clamp_next(cost_ * target / last_ms_);
      break;
    case AdaptMode::predict: {
      const double now = predict_ms ? predict_ms(cost_) : NAN;
      if (!(std::isfinite(now) && now > 0)) break;
      // Extrapolation: time proportional to the cost factor.
      double guess = clamp_next(cost_ * target / now);
      // Bisection on predictions: the largest c in [lo, hi] predicted within the target.
      const double ceiling = clamp_next(1.0);
      double lo = config_.min_cost, hi = ceiling;
      const double at_guess = predict_ms(guess);
      if (std::isfinite(at_guess) && at_guess <= target)
        lo = guess;
      else
        hi = guess;
      for (int i = 0; i < config_.bisection_steps && hi - lo > 1e-4 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        const double t = predict_ms(mid);
        (std::isfinite(t) && t <= target ? lo : hi) = mid;
      }
      const double at_hi = predict_ms(hi);
      cost_ = std::isfinite(at_hi) && at_hi <= target ? hi : lo;
      break;
    }
  }
  return cost_;
}

std::optional<double> FrameTimeTargeting::second_pass(double first_ms) {
  const double target = config_.target_ms;
  if (config_.mode != AdaptMode::two_pass || !(std::isfinite(first_ms) && first_ms > 0) ||
      first_ms >= 0.5 * target)
    return std::nullopt;
  cost_ = std::clamp(config_.probe_cost * (target - first_ms) / first_ms, config_.min_cost, 1.0);
  return cost_;
}

void FrameTimeTargeting::measured(double frame_ms) {
  if (std::isfinite(frame_ms) && frame_ms > 0) last_ms_ = frame_ms;
}

}  // namespace multiray::balance
