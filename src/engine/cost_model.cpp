#include "engine/cost_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <dlib/svm.h>

namespace multiray {

namespace {
constexpr long kFeatures = long(std::tuple_size<CostFeatures>::value);
using Sample = dlib::matrix<double, kFeatures, 1>;
using Rbf = dlib::radial_basis_kernel<Sample>;
// ours(): features vary over about one unit each (cost_model.h), so γ 0.5 makes frames a
// unit apart in one feature still inform each other, and tolerance 0.001 keeps about a
// hundred frames' worth of support vectors (PLATFORM.md measured ~40 us per training step
// at that size). The paper's γ 0.00025 is for its own, unscaled features: a kernel width
// of ~63 units, which the pre-pass time (ms) and the ray span (voxels) vary over.
}  // namespace

CostModelConfig parse_cost_model(const std::string& text) {
  const size_t colon = text.find(':');
  const std::string name = text.substr(0, colon);
  CostModelConfig c;
  if (name == "paper")
    c = CostModelConfig::paper();
  else if (name != "ours")
    throw std::invalid_argument("cost model '" + text +
                                "' must be ours[:tf=0|1] or paper[:tf=0|1]");
  if (colon == std::string::npos) return c;
  const std::string option = text.substr(colon + 1);
  if (option != "tf=0" && option != "tf=1")
    throw std::invalid_argument("cost model '" + text + "': the only option is tf=0|1");
  c.transfer_feature = option == "tf=1";
  return c;
}

struct CostModel::Impl {
  explicit Impl(const CostModelConfig& c) : krls(Rbf(c.gamma), c.tolerance, c.max_dictionary) {}
  dlib::krls<Rbf> krls;
};

CostModel::CostModel(const CostModelConfig& config)
    : config_(config), impl_(std::make_unique<Impl>(config)) {
  if (!(config.gamma > 0 && config.tolerance > 0 && config.max_dictionary > 0))
    throw std::invalid_argument("cost model: gamma, tolerance and dictionary must be > 0");
}
CostModel::~CostModel() = default;
CostModel::CostModel(CostModel&&) noexcept = default;
CostModel& CostModel::operator=(CostModel&&) noexcept = default;

namespace {
double log2_clamped(double x) { return std::log2(std::max(x, 1e-9)); }

// The features as the model takes them (cost_model.h): scaled to about a unit each for
// ours, as measured for the paper's; the transfer function's held at 0 when left out.
Sample sample_of(const CostFeatures& x, const CostModelConfig& c) {
  Sample s;
  for (long i = 0; i < kFeatures; ++i) s(i) = x[size_t(i)];
  if (c.scaled_features) {
    s(2) = log2_clamped(x[2]);
    s(3) = log2_clamped(x[3]);
    s(4) = log2_clamped(1 + x[4]);
    s(5) = x[5] / 256;
  }
  if (!c.transfer_feature) s(long(kTransferFeature)) = 0;
  return s;
}
}  // namespace

void CostModel::train(const CostFeatures& x, double sigma) {
  if (!(std::isfinite(sigma) && sigma > 0)) return;
  for (double f : x)
    if (!std::isfinite(f)) return;
  const Sample s = sample_of(x, config_);
  ++observations_;
  if (!config_.log_cost) {
    impl_->krls.train(s, sigma);
    return;
  }
  // Ours learns log(sigma) relative to the first observation: costs span orders of
  // magnitude across devices, and an RBF regressor tends to 0 far from its data, which
  // then means "the cost first seen" rather than "free".
  const double y = std::log(sigma);
  if (observations_ == 1) mean_log_ = y;
  impl_->krls.train(s, y - mean_log_);
}

double CostModel::predict(const CostFeatures& x) const {
  if (observations_ == 0) return 0;
  const double y = impl_->krls(sample_of(x, config_));
  if (!config_.log_cost) return std::isfinite(y) && y > 0 ? y : 0;
  const double sigma = std::exp(y + mean_log_);
  return std::isfinite(sigma) ? sigma : 0;
}

}  // namespace multiray
