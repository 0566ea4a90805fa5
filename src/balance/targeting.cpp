#include "balance/targeting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "util/parse.h"

namespace multiray::balance {

AdaptMode parse_adapt_mode(const std::string& text) {
  if (text == "none") return AdaptMode::none;
  if (text == "last-frame") return AdaptMode::last_frame;
  if (text == "predict") return AdaptMode::predict;
  if (text == "two-pass") return AdaptMode::two_pass;
  throw std::invalid_argument("adaptation mode '" + text +
                              "' must be none, last-frame, predict or two-pass");
}

void parse_adapt(const std::string& text, TargetingConfig& config) {
  const size_t colon = text.find(':');
  config.mode = parse_adapt_mode(text.substr(0, colon));
  config.margin_quantile = 0;
  config.probe_fixed = false;
  if (colon == std::string::npos) return;
  const std::string option = text.substr(colon + 1);
  if (config.mode == AdaptMode::two_pass && (option == "probe=fixed" || option == "probe=last")) {
    config.probe_fixed = option == "probe=fixed";
    return;
  }
  if (config.mode != AdaptMode::predict || option.rfind("q=", 0) != 0)
    throw std::invalid_argument("adaptation mode '" + text +
                                "': only predict:q=Q (e.g. predict:q=0.9) and "
                                "two-pass:probe=fixed|last take an option");
  const double q = parse_number(option.substr(2)).value_or(NAN);
  if (!(q > 0 && q < 1))
    throw std::invalid_argument("adaptation mode '" + text + "': q must be a number in (0, 1)");
  config.margin_quantile = q;
}

std::string adapt_name(const TargetingConfig& config) {
  std::string name = adapt_mode_name(config.mode);
  if (config.mode == AdaptMode::predict && config.margin_quantile > 0) {
    char q[32];
    std::snprintf(q, sizeof q, ":q=%g", config.margin_quantile);
    name += q;
  }
  if (config.mode == AdaptMode::two_pass && config.probe_fixed) name += ":probe=fixed";
  return name;
}

AdaptSpace parse_adapt_space(const std::string& text) {
  if (text == "ray") return AdaptSpace::ray;
  if (text == "image") return AdaptSpace::image;
  if (text == "hybrid") return AdaptSpace::hybrid;
  if (text == "auto") return AdaptSpace::automatic;
  throw std::invalid_argument("adaptation space '" + text +
                              "' must be auto, ray, image or hybrid");
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
  switch (s) {
    case AdaptSpace::ray:
      return "ray";
    case AdaptSpace::image:
      return "image";
    case AdaptSpace::hybrid:
      return "hybrid";
    case AdaptSpace::automatic:
      return "auto";
  }
  return "?";
}

Quality quality_of(double cost, AdaptSpace space) {
  Quality q;
  if (space == AdaptSpace::ray) q.step_scale = 1 / cost;
  if (space == AdaptSpace::image) q.image_scale = std::sqrt(cost);
  if (space == AdaptSpace::hybrid)
    q.image_scale = std::pow(cost, 0.25), q.step_scale = 1 / std::sqrt(cost);
  if (space == AdaptSpace::automatic) {
    // Fewer pixels first (they shrink every part of a ray's work), then a longer step,
    // bounded: past kAutoStepCeiling the lattice of samples shows as slabs and rings.
    constexpr double knee = kAutoImageFloor * kAutoImageFloor;  // the image's share at its floor
    if (cost >= knee) {
      q.image_scale = std::sqrt(cost);
    } else {
      q.image_scale = kAutoImageFloor;
      q.step_scale = std::min(knee / cost, kAutoStepCeiling);
    }
  }
  return q;
}

double lowest_cost(const TargetingConfig& config) {
  return config.space == AdaptSpace::automatic ? std::max(config.min_cost, kAutoLowestCost)
                                               : config.min_cost;
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
  if (!(config.margin_quantile >= 0 && config.margin_quantile < 1))
    throw std::invalid_argument("the prediction margin quantile must be in [0, 1)");
  config_.min_cost = lowest_cost(config);
  if (config_.probe_cost < config_.min_cost) config_.probe_cost = config_.min_cost;
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
      // The paper: a quarter of the last frame's parameters (cost_ is its last pass).
      probe_ = config_.probe_fixed ? config_.probe_cost
                                   : std::clamp(config_.probe_cost * cost_, config_.min_cost, 1.0);
      cost_ = probe_;
      break;
    case AdaptMode::last_frame:
      if (last_ms_ > 0) cost_ = clamp_next(cost_ * target / last_ms_);
      break;
    case AdaptMode::predict: {
      predicted_ms_ = 0;
      if (!predict_ms) break;
      const double k = calibration();
      const std::function<double(double)> predict = [&](double c) { return k * predict_ms(c); };
      choose_predicted(predict);
      const double at = predict_ms(cost_);
      if (std::isfinite(at) && at > 0) predicted_ms_ = at;
      break;
    }
  }
  return cost_;
}

void FrameTimeTargeting::choose_predicted(const std::function<double(double)>& predict_ms) {
  const double target = config_.target_ms;
  const double now = predict_ms(cost_);
  if (!(std::isfinite(now) && now > 0)) return;
  // Extrapolation: time proportional to the cost factor.
  const double guess = clamp_next(cost_ * target / now);
  // Bisection on predictions: the largest c in [lo, hi] predicted within the target.
  double lo = config_.min_cost, hi = clamp_next(1.0);
  const double at_guess = predict_ms(guess);
  (std::isfinite(at_guess) && at_guess <= target ? lo : hi) = guess;
  for (int i = 0; i < config_.bisection_steps && hi - lo > 1e-4 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double t = predict_ms(mid);
    (std::isfinite(t) && t <= target ? lo : hi) = mid;
  }
  const double at_hi = predict_ms(hi);
  cost_ = std::isfinite(at_hi) && at_hi <= target ? hi : lo;
}

double FrameTimeTargeting::calibration() const {
  if (!(config_.margin_quantile > 0) || ratios_.size() < kMinRatios) return 1;
  std::vector<double> sorted(ratios_.begin(), ratios_.end());
  const size_t at = std::min(
      sorted.size() - 1, size_t(std::ceil(config_.margin_quantile * double(sorted.size())) - 1));
  std::nth_element(sorted.begin(), sorted.begin() + long(at), sorted.end());
  return sorted[at];
}

std::optional<double> FrameTimeTargeting::second_pass(double first_ms) {
  const double target = config_.target_ms;
  if (config_.mode != AdaptMode::two_pass || !(std::isfinite(first_ms) && first_ms > 0) ||
      first_ms >= 0.5 * target)
    return std::nullopt;
  cost_ = std::clamp(probe_ * (target - first_ms) / first_ms, config_.min_cost, 1.0);
  return cost_;
}

void FrameTimeTargeting::set_target_ms(double ms) {
  if (!(std::isfinite(ms) && ms > 0))
    throw std::invalid_argument("the target frame time must be a finite number of ms > 0");
  config_.target_ms = ms;
}

void FrameTimeTargeting::measured(double frame_ms) {
  if (!(std::isfinite(frame_ms) && frame_ms > 0)) return;
  last_ms_ = frame_ms;
  if (predicted_ms_ > 0) {
    ratios_.push_back(frame_ms / predicted_ms_);
    if (ratios_.size() > kMaxRatios) ratios_.pop_front();
  }
}

}  // namespace multiray::balance
