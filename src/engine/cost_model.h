// The learned half of Bruder, Frey & Ertl's hybrid cost model (2017, §5.1): a device's
// cost per volume sample, sigma (ms), as a smooth function of features of the frame,
// learned online by kernel recursive least squares (Engel, Mannor & Meir 2004) with an
// RBF kernel — dlib's krls, as the paper uses. Trained after every frame; predicting costs
// about a microsecond.
#pragma once

#include <array>
#include <memory>
#include <string>

namespace multiray {

// The features of a frame, in the units they are measured in: view direction angles
// (azimuth, elevation, radians), voxel footprint (the pixel size at the volume centre over
// the voxel length), step size (voxel lengths), pre-pass time (ms), longest ray span
// (voxel lengths) — the paper's five kinds (Bruder et al. §5.1) — and ours, the transfer
// function's work per sample: the share of the frame's predicted samples that the
// transfer function makes visible (shaded, 7 fetches) rather than transparent (1 fetch),
// in [0, 1], from the pre-pass with the frame's own transfer function, so it changes on
// the frame of a switch. A model encodes them as its settings say (CostModelConfig).
using CostFeatures = std::array<double, 7>;
constexpr size_t kTransferFeature = 6;  // index of the transfer function's feature

// KRLS settings. paper(): the paper's model as it states it — γ = 0.00025, tolerance
// 0.006, a dictionary of up to 10 million, its own features unscaled, no
// transfer-function feature, and the cost per sample σ itself as the target. ours(): γ =
// 0.5 on features scaled to vary over about one unit each (log2 of footprint, step and
// 1 + pre-pass ms; span / 256), tolerance 0.001, at most 200 support vectors, the
// transfer-function feature, and log σ relative to the first observation as the target.
struct CostModelConfig {
  double gamma = 0.5;
  double tolerance = 0.001;
  unsigned max_dictionary = 200;
  bool transfer_feature = true;
  bool scaled_features = true;  // false: the features as measured (the paper's)
  bool log_cost = true;         // false: learn σ itself (the paper's)

  static CostModelConfig ours() { return {}; }
  static CostModelConfig paper() { return {0.00025, 0.006, 10000000, false, false, false}; }
};
// "ours" | "paper", each optionally followed by ":tf=0" or ":tf=1" (without or with the
// transfer-function feature: ours has it, the paper's not); std::invalid_argument (one
// line) otherwise.
CostModelConfig parse_cost_model(const std::string& text);

class CostModel {
 public:
  explicit CostModel(const CostModelConfig& config = CostModelConfig::ours());
  ~CostModel();
  CostModel(CostModel&&) noexcept;
  CostModel& operator=(CostModel&&) noexcept;

  // Adds one observation: at these features the device took `sigma` ms per sample.
  // Non-finite or non-positive sigmas are ignored.
  void train(const CostFeatures& x, double sigma);
  // Predicted sigma at `x`; 0 before the first observation, and 0 where a model of σ
  // itself (paper()) predicts none above 0 (an RBF regressor tends to 0 far from its data).
  double predict(const CostFeatures& x) const;
  int observations() const { return observations_; }
  const CostModelConfig& config() const { return config_; }

 private:
  struct Impl;
  CostModelConfig config_;
  std::unique_ptr<Impl> impl_;
  int observations_ = 0;
  double mean_log_ = 0;  // log_cost: KRLS learns log(sigma) relative to the first one's
};

}  // namespace multiray
