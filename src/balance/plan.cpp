#include "balance/plan.h"

#include <cmath>
#include <stdexcept>

#include "partition/coverage.h"

namespace multiray::balance {

void validate_shape(const FrameShape& shape) {
  if (shape.width < 0 || shape.height < 0)
    throw std::invalid_argument("frame size " + std::to_string(shape.width) + "x" +
                                std::to_string(shape.height) + " is negative");
  if (shape.views < 1)
    throw std::invalid_argument("frame has " + std::to_string(shape.views) +
                                " views, need at least 1");
  if (!shape.pixel_weight.empty() && int64_t(shape.pixel_weight.size()) != shape.pixels())
    throw std::invalid_argument(
        "pixel_weight has " + std::to_string(shape.pixel_weight.size()) +
        " values, expected views*height*width = " + std::to_string(shape.pixels()));
}

std::vector<WorkItem> Plan::all_items() const {
  std::vector<WorkItem> items;
  for (const auto& list : assigned) items.insert(items.end(), list.begin(), list.end());
  items.insert(items.end(), shared.begin(), shared.end());
  return items;
}

std::string check_plan(const Plan& plan, const FrameShape& shape, int device_count) {
  if (int(plan.assigned.size()) != device_count)
    return "plan has " + std::to_string(plan.assigned.size()) + " device lists for " +
           std::to_string(device_count) + " devices";
  if (int(plan.ratios.size()) != device_count)
    return "plan has " + std::to_string(plan.ratios.size()) + " ratios for " +
           std::to_string(device_count) + " devices";
  if (plan.batch < 1) return "batch " + std::to_string(plan.batch) + " < 1";
  double sum = 0;
  for (double r : plan.ratios) {
    if (!std::isfinite(r) || r < 0)
      return "ratio " + std::to_string(r) + " is not finite and >= 0";
    sum += r;
  }
  if (sum != 0 && std::abs(sum - 1) > 1e-9) return "ratios sum to " + std::to_string(sum);
  return coverage_error(plan.all_items(), shape.width, shape.height, shape.views);
}

}  // namespace multiray::balance
