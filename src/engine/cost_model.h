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

// The paper's features: view direction angles (azimuth, elevation, radians), voxel
// footprint (log2 of the pixel size at the volume centre over the voxel length), step
// size (log2, voxel lengths), pre-pass time (log2 of 1 + ms), longest ray span (voxel
// lengths / 256); and ours, the transfer function's work per sample: the share of the
// frame's predicted samples that the transfer function makes visible (shaded, 7 fetches)
// rather than transparent (1 fetch), in [0, 1], from the pre-pass with the frame's own
// transfer function, so it changes on the frame of a switch. Scaled so that each varies
// over about one unit, which the kernel width assumes.
using CostFeatures = std::array<double, 7>;
constexpr size_t kTransferFeature = 6;  // index of the transfer function's feature

// KRLS settings. ours(): RBF γ = 0.5 on the unit-scaled features, dictionary tolerance
// 0.001, at most 200 support vectors. paper(): the paper's γ = 0.00025 and tolerance
// 0.006 (no cap on the dictionary; at that width it stays small). `transfer_feature`
// false leaves feature 6 out (held at 0), as the paper's model has no such feature.
struct CostModelConfig {
  double gamma = 0.5;
  double tolerance = 0.001;
  unsigned max_dictionary = 200;
  bool transfer_feature = true;

  static CostModelConfig ours() { return {}; }
  static CostModelConfig paper() { return {0.00025, 0.006, 1000000, true}; }
};
// "ours" | "paper", each optionally followed by ":tf=0" (no transfer-function feature);
// std::invalid_argument (one line) otherwise.
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
  // Predicted sigma at `x`; 0 before the first observation.
  double predict(const CostFeatures& x) const;
  int observations() const { return observations_; }
  const CostModelConfig& config() const { return config_; }

 private:
  struct Impl;
  CostModelConfig config_;
  std::unique_ptr<Impl> impl_;
  int observations_ = 0;
  double mean_log_ = 0;  // KRLS learns log(sigma) relative to the first observation's
};

}  // namespace multiray
