#include "balance/uniform.h"

namespace multiray::balance {

UniformBalancer::UniformBalancer(int device_count, Layout layout)
    : BalancerBase(device_count), layout_(layout) {}

std::string UniformBalancer::spec() const { return "uniform:layout=" + to_string(layout_); }

Plan UniformBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  return plan_from_ratios(shape, even(), layout_);
}

}  // namespace multiray::balance
