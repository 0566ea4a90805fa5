// Frame-time targeting (Bruder, Frey & Ertl 2017, §6.1): choose each frame's quality so
// that it takes a user's target time. Quality is one number, the cost factor c in
// [min_cost, 1] (1 = full quality): the share of the full-quality work the frame does,
// spent in ray space (a longer step: step_scale = 1/c), image space (fewer pixels:
// image_scale = sqrt(c)), both (hybrid: image_scale = c^(1/4), step_scale = c^(-1/2)), or,
// the default (auto, ours), the reduction that degrades least first: image space down to
// half the resolution per side, then a longer step up to x2, and no further (c >= 1/8).
// A volume sampled at a step several times the user's shows slabs and rings (the lattice
// t_entry + k·Δ of every ray is visible), and a step does not shrink the per-ray and
// per-block work, so a coarse step buys little time for much damage; fewer pixels shrink
// every part of a ray's work and blur evenly. The paper's spaces (ray, image, hybrid) keep
// their reach down to 1/64. Pure policy over numbers, like the balancers.
//
// Modes (all in one run of `multiray bench` to compare, as the paper's Fig. 5a):
//  - none: always full quality;
//  - last-frame: scale c by target / (last measured frame time) — the usual reactive
//    method, which overshoots whenever the cost changes suddenly (a transfer-function
//    switch, a camera cut);
//  - predict: the paper's Eq. 2 — with a predictor of the frame time at any c (the
//    renderer's cost model, evaluated before rendering), extrapolate from the last c,
//    then refine by bisection on predictions to the largest c predicted to meet the target.
//    Ours, `predict:q=Q`: the predictions are first scaled by the Q-quantile of the last
//    frames' measured / predicted times, so a biased or noisy predictor still lands at or
//    under the target in a share Q of the frames (the paper aims at the prediction itself);
//  - two-pass: the paper's other baseline — every frame first renders at `probe_cost`
//    (a quarter) times the last frame's cost factor, i.e. at a quarter of the last frame's
//    parameters; if that pass took under half the target, a second pass at the cost factor
//    extrapolated to fill the rest of the budget replaces its image (second_pass()). It
//    measures instead of predicting, and pays for the probe every frame. Ours,
//    `two-pass:probe=fixed`: the first pass is always at `probe_cost` of full quality.
// In the last-frame and predict modes quality rises by at most 1/`max_raise` per frame
// (the paper: the step shrinks by at most x0.8 a frame), so a transient lull does not
// cause a spike; two-pass measures the frame itself and needs no such limit.
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <string>

#include "balance/plan.h"

namespace multiray::balance {

enum class AdaptMode { none, last_frame, predict, two_pass };
enum class AdaptSpace { ray, image, hybrid, automatic };

// The auto space's bounds: the image shrinks to kAutoImageFloor per side before the step
// grows, and the step grows to kAutoStepCeiling at most, so its cost factor stops at
// kAutoImageFloor^2 / kAutoStepCeiling = kAutoLowestCost.
constexpr double kAutoImageFloor = 0.5, kAutoStepCeiling = 2.0;
constexpr double kAutoLowestCost = kAutoImageFloor * kAutoImageFloor / kAutoStepCeiling;

struct TargetingConfig {
  double target_ms = 0;  // > 0
  AdaptMode mode = AdaptMode::none;
  AdaptSpace space = AdaptSpace::ray;
  // Lowest cost factor (coarsest quality), in (0, 1]; in the auto space at least
  // kAutoLowestCost whatever is set here (lowest_cost()).
  double min_cost = 1.0 / 64;
  double max_raise = 0.8;  // c_next <= c / max_raise, in (0, 1]
  int bisection_steps = 12;
  // two-pass: the first pass's cost factor relative to the last frame's (the paper), or,
  // with probe_fixed (ours), relative to full quality; in [min_cost, 1].
  double probe_cost = 0.25;
  bool probe_fixed = false;
  // predict: 0 for the paper's form, else the quantile Q in (0, 1) of the recent measured /
  // predicted ratios that scales the predictions (calibrated once kMinRatios are known).
  double margin_quantile = 0;
};

// "none" | "last-frame" | "predict" | "two-pass", "ray" | "image" | "hybrid";
// std::invalid_argument (one line) otherwise.
AdaptMode parse_adapt_mode(const std::string& text);
// A mode with its options into `config` (mode, margin_quantile, probe_fixed): a mode
// name, "predict:q=Q" with Q in (0, 1) or "two-pass:probe=fixed" (ours) /
// "two-pass:probe=last" (the paper's, the default). std::invalid_argument (one line)
// otherwise.
void parse_adapt(const std::string& text, TargetingConfig& config);
// The spec of config's mode as parse_adapt reads it ("predict:q=0.9", "last-frame",
// "two-pass:probe=fixed").
std::string adapt_name(const TargetingConfig& config);
// "ray" | "image" | "hybrid" | "auto"; std::invalid_argument (one line) otherwise.
AdaptSpace parse_adapt_space(const std::string& text);
const char* adapt_mode_name(AdaptMode m);
const char* adapt_space_name(AdaptSpace s);

// The quality of cost factor c in `space` (in auto, c below kAutoLowestCost gets the
// quality of kAutoLowestCost: the step stays bounded).
Quality quality_of(double cost, AdaptSpace space);
// The lowest cost factor `config` lets targeting choose: its min_cost, raised to
// kAutoLowestCost in the auto space.
double lowest_cost(const TargetingConfig& config);

class FrameTimeTargeting {
 public:
  // Throws std::invalid_argument for a target that is not finite and > 0, or bounds out
  // of range. The cost factor stays within [lowest_cost(config), 1].
  explicit FrameTimeTargeting(const TargetingConfig& config);

  // The cost factor of the next frame. `predict_ms(c)`, when the mode is predict, gives
  // the predicted frame time at cost factor c (it may return a non-finite or
  // non-positive number when it cannot predict yet: the factor is then kept).
  double next(const std::function<double(double)>& predict_ms);
  // Two-pass mode, after the first pass of a frame took `first_ms`: the cost factor of a
  // second pass that fits the rest of the target (time taken as proportional to the cost
  // factor, from the first pass's), or none when the first pass used half the target or more (it
  // is then the frame), when the time is garbage or in any other mode.
  std::optional<double> second_pass(double first_ms);
  // Tells the measured time of the frame last planned (ms; garbage is ignored).
  void measured(double frame_ms);

  double cost() const { return cost_; }
  // A new target for the following frames (a live viewer's slider); throws
  // std::invalid_argument unless finite and > 0.
  void set_target_ms(double ms);
  // The factor predictions are scaled by in predict:q=Q (1 until calibrated).
  double calibration() const;

  static constexpr size_t kMinRatios = 5, kMaxRatios = 30;
  const TargetingConfig& config() const { return config_; }

 private:
  double clamp_next(double wanted) const;
  // Predict mode: Eq. 2 over `predict_ms` into cost_ (kept when it cannot predict).
  void choose_predicted(const std::function<double(double)>& predict_ms);

  TargetingConfig config_;
  double cost_ = 1.0;          // of the frame last planned (its last pass)
  double probe_ = 1.0;         // two-pass: the cost factor of this frame's first pass
  double last_ms_ = 0.0;       // its measured time, 0 until known
  double predicted_ms_ = 0.0;  // its predicted time (predict mode), 0 when unknown
  std::deque<double> ratios_;  // measured / predicted of the last frames, oldest first
};

}  // namespace multiray::balance
