#include "engine/cost_model.h"

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
// at that size). The paper's γ 0.00025 was set for its own, unscaled features.
}  // namespace

CostModelConfig parse_cost_model(const std::string& text) {
  const size_t colon = text.find(':');
  const std::string name = text.substr(0, colon);
  CostModelConfig c;
  if (name == "paper")
    c = CostModelConfig::paper();
  else if (name != "ours")
    throw std::invalid_argument("cost model '" + text + "' must be ours or paper[:tf=0|1]");
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
Sample sample_of(const CostFeatures& x, bool transfer_feature) {
  Sample s;
  for (long i = 0; i < kFeatures; ++i) s(i) = x[size_t(i)];
  if (!transfer_feature) s(long(kTransferFeature)) = 0;
  return s;
}
}  // namespace

void CostModel::train(const CostFeatures& x, double sigma) {
  if (!(std::isfinite(sigma) && sigma > 0)) return;
  for (double f : x)
    if (!std::isfinite(f)) return;
  // The model learns log(sigma) relative to the first observation: costs span orders of
  // magnitude across devices, and an RBF regressor tends to 0 far from its data, which
  // then means "the cost first seen" rather than "free".
  const double y = std::log(sigma);
  if (observations_++ == 0) mean_log_ = y;
  impl_->krls.train(sample_of(x, config_.transfer_feature), y - mean_log_);
}

double CostModel::predict(const CostFeatures& x) const {
  if (observations_ == 0) return 0;
  const double y = impl_->krls(sample_of(x, config_.transfer_feature)) + mean_log_;
  return std::isfinite(y) ? std::exp(y) : 0;
}

}  // namespace multiray
