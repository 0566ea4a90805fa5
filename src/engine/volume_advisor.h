// Bruder, Frey & Ertl's prediction for the volume raycaster (2017, §4–5) behind the
// FrameAdvisor seam: before each frame a pre-pass (render/volume_prepass.h) predicts the
// samples every pixel will take; per device a KRLS model (cost_model.h) predicts the cost
// per sample sigma_i from features of the frame. Their product is the paper's analytic
// frame cost t' = 7·(d_back − d_front)/Δ·σ (the 7 fetches per sample are inside σ), per
// pixel for the balancer and per frame for frame-time targeting (balance/targeting.h).
// After the frame each device's measured time over the predicted samples it rendered
// trains its model.
#pragma once

#include <memory>
#include <vector>

#include "balance/targeting.h"
#include "engine/cost_model.h"
#include "engine/frame_advisor.h"
#include "render/volume_raycaster.h"

namespace multiray {

struct VolumeAdvisorConfig {
  // Mode none still predicts (balancers that use predictions split by them, and the
  // prediction error is recorded) but always renders at full quality.
  balance::TargetingConfig targeting;
  int prepass_stride = 4;      // one pre-pass ray per stride x stride pixels
  CostModelConfig cost_model;  // KRLS settings and features (cost_model.h)
  uint64_t seed = 0;
};

// Where the advisor's time went in the last frame (the paper's Table 3), ms.
struct AdvisorTimings {
  double prepass_ms = 0, predict_ms = 0, train_ms = 0;
};

// The transfer function's cost feature (cost_model.h): the share of shaded samples among
// a pre-pass's samples, from its fetch-weighted length `weighted` (a shaded sample 1, a
// transparent one 1/7) and its plain length `marched`; in [0, 1], 0 when nothing marched.
double shaded_share(double weighted, double marched);

class VolumeAdvisor : public FrameAdvisor {
 public:
  // Throws std::invalid_argument for a bad targeting configuration.
  VolumeAdvisor(const VolumeScene& vs, int device_count, const VolumeAdvisorConfig& config);

  FrameAdvice advise(int frame, const std::vector<ViewSetup>& views,
                     const RenderSettings& settings) override;
  void measured(const FrameAdvice& advice, const FrameRecord& record,
                const balance::FrameStats& stats) override;
  // Two-pass targeting (balance/targeting.h): a second pass when the first left time.
  std::optional<FrameAdvice> second_pass(const FrameAdvice& first,
                                         const FrameRecord& first_pass) override;

  // Records predicted_sigma() and measured_sigma() in the frame's record.
  void annotate(FrameRecord& record) const override {
    record.predicted_cost = predicted_sigma_;
    record.measured_cost = measured_sigma_;
  }

  const AdvisorTimings& timings() const { return timings_; }
  // Each device's sigma predicted for the last frame and the one measured after it (ms
  // per sample; 0 where unknown), for the prediction-error plots (paper Fig. 6a).
  const std::vector<double>& predicted_sigma() const { return predicted_sigma_; }
  const std::vector<double>& measured_sigma() const { return measured_sigma_; }
  // The features of the frame last advised, at its chosen quality (cost_model.h).
  const CostFeatures& last_features() const { return last_features_; }
  double cost_factor() const { return targeting_.cost(); }
  // Whether it adapts quality to a frame-time target (an --adapt mode other than none).
  bool targets_frame_time() const { return config_.targeting.mode != balance::AdaptMode::none; }
  // The frame-time target of the following frames (ms, finite and > 0).
  void set_target_ms(double ms) { targeting_.set_target_ms(ms), config_.targeting.target_ms = ms; }

 private:
  // The features at `step_scale` from the last pre-pass.
  CostFeatures features(double step_scale) const;
  // Predicted frame time at cost factor c from the last pre-pass (NaN while a live device
  // has no model).
  double predict_ms(double c) const;
  // Fills the quality, predictions and per-pixel work of `advice` at cost factor c.
  void advice_at(double c, FrameAdvice& advice);

  const VolumeScene& vs_;
  VolumeAdvisorConfig config_;
  balance::FrameTimeTargeting targeting_;
  std::vector<CostModel> models_;
  std::vector<bool> alive_;
  // The last frame's inputs, for training after it.
  ViewSetup view_;
  std::shared_ptr<const VolumeStyle> style_;
  double prepass_ms_ = 0, max_depth_ = 0;
  double shaded_share_ = 0;  // of the pre-pass's samples: the transfer function's feature
  CostFeatures last_features_{};
  // The pre-pass's samples of each output pixel at the full-quality step and the work the
  // step does not change (samples' worth), and their sums.
  std::vector<float> samples_, fixed_;
  double full_samples_ = 0, fixed_samples_ = 0;
  AdvisorTimings timings_;
  std::vector<double> predicted_sigma_, measured_sigma_;
};

}  // namespace multiray
