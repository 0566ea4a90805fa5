// The learned half of Bruder, Frey & Ertl's hybrid cost model (2017, §5.1): a device's
// cost per volume sample, sigma (ms), as a smooth function of features of the frame,
// learned online by kernel recursive least squares (Engel, Mannor & Meir 2004) with an
// RBF kernel — dlib's krls, as the paper uses. Trained after every frame; predicting costs
// about a microsecond.
#pragma once

#include <array>
#include <memory>

namespace multiray {

// The paper's features: view direction angles (azimuth, elevation, radians), voxel
// footprint (log2 of the pixel size at the volume centre over the voxel length), step
// size (log2, voxel lengths), pre-pass time (log2 of 1 + ms), longest ray span (voxel
// lengths / 256). Scaled so that each varies over about one unit, which the kernel width
// assumes.
using CostFeatures = std::array<double, 6>;

class CostModel {
 public:
  CostModel();
  ~CostModel();
  CostModel(CostModel&&) noexcept;
  CostModel& operator=(CostModel&&) noexcept;

  // Adds one observation: at these features the device took `sigma` ms per sample.
  // Non-finite or non-positive sigmas are ignored.
  void train(const CostFeatures& x, double sigma);
  // Predicted sigma at `x`; 0 before the first observation.
  double predict(const CostFeatures& x) const;
  int observations() const { return observations_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int observations_ = 0;
  double mean_log_ = 0;  // KRLS learns log(sigma) relative to the first observation's
};

}  // namespace multiray
