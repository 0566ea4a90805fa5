#include "balance/uniform.h"

namespace multiray::balance {

UniformBalancer::UniformBalancer(int device_count, Layout layout, StripRule strips)
    : BalancerBase(device_count), layout_(layout), strips_(strips) {}

std::string UniformBalancer::spec() const {
  const std::string s = "uniform:layout=" + to_string(layout_);
  return layout_ == Layout::Strips ? s + ":" + to_spec(strips_) : s;
}

Plan UniformBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  if (alive_count() == 0) return empty_plan();
  return plan_from_ratios(shape, even(), layout_, strips_);
}

}  // namespace multiray::balance
