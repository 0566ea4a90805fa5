#include "engine/cost_model.h"

#include <cmath>

#include <dlib/svm.h>

namespace multiray {

namespace {
using Sample = dlib::matrix<double, 6, 1>;
using Rbf = dlib::radial_basis_kernel<Sample>;
// Kernel width: features vary over about one unit each (cost_model.h), so gamma 0.5 makes
// frames a unit apart in one feature still inform each other. Dictionary tolerance 0.001
// keeps about a hundred frames' worth of support vectors (PLATFORM.md measured ~40 us per
// training step at that size).
constexpr double kGamma = 0.5, kTolerance = 0.001;
constexpr unsigned kMaxDictionary = 200;
}  // namespace

struct CostModel::Impl {
  dlib::krls<Rbf> krls{Rbf(kGamma), kTolerance, kMaxDictionary};
};

CostModel::CostModel() : impl_(std::make_unique<Impl>()) {}
CostModel::~CostModel() = default;
CostModel::CostModel(CostModel&&) noexcept = default;
CostModel& CostModel::operator=(CostModel&&) noexcept = default;

void CostModel::train(const CostFeatures& x, double sigma) {
  if (!(std::isfinite(sigma) && sigma > 0)) return;
  for (double f : x)
    if (!std::isfinite(f)) return;
  // The model learns log(sigma) relative to the first observation: costs span orders of
  // magnitude across devices, and an RBF regressor tends to 0 far from its data, which
  // then means "the cost first seen" rather than "free".
  const double y = std::log(sigma);
  if (observations_++ == 0) mean_log_ = y;
  Sample s;
  for (int i = 0; i < 6; ++i) s(i) = x[size_t(i)];
  impl_->krls.train(s, y - mean_log_);
}

double CostModel::predict(const CostFeatures& x) const {
  if (observations_ == 0) return 0;
  Sample s;
  for (int i = 0; i < 6; ++i) s(i) = x[size_t(i)];
  const double y = impl_->krls(s) + mean_log_;
  return std::isfinite(y) ? std::exp(y) : 0;
}

}  // namespace multiray
