#include "balance/plan.h"

#include <algorithm>
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

FrameShape scaled_shape(const FrameShape& shape, double image_scale) {
  if (!(image_scale > 0 && image_scale <= 1))
    throw std::invalid_argument("image scale " + std::to_string(image_scale) +
                                " is outside (0, 1]");
  if (image_scale == 1) return shape;
  auto side = [&](int n) { return std::max(1, int(std::lround(double(n) * image_scale))); };
  FrameShape out;
  out.width = side(shape.width);
  out.height = side(shape.height);
  out.views = shape.views;
  out.device_cost = shape.device_cost;
  if (shape.weighted()) {
    out.pixel_weight.reserve(size_t(out.pixels()));
    for (int v = 0; v < out.views; ++v)
      for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
          const int64_t sx = int64_t(x) * shape.width / out.width;
          const int64_t sy = int64_t(y) * shape.height / out.height;
          out.pixel_weight.push_back(
              shape.pixel_weight[size_t((v * int64_t(shape.height) + sy) * shape.width + sx)]);
        }
  }
  return out;
}

std::vector<WorkItem> Plan::all_items() const {
  std::vector<WorkItem> items;
  for (const auto& list : assigned) items.insert(items.end(), list.begin(), list.end());
  items.insert(items.end(), shared.begin(), shared.end());
  return items;
}

namespace {

bool has_work(const Plan& plan) {
  for (const WorkItem& item : plan.all_items())
    if (!item.rect.empty()) return true;
  return false;
}

}  // namespace

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
  // All 0 only for a plan with no work (every device dropped, a frame without pixels):
  // ratios of 0 for work to be done say nothing of who does it.
  if (std::abs(sum - 1) > 1e-9 && (sum != 0 || has_work(plan)))
    return "ratios sum to " + std::to_string(sum) + ", not 1";
  if (!plan.no_steal.empty() && int(plan.no_steal.size()) != device_count)
    return "plan says of " + std::to_string(plan.no_steal.size()) +
           " devices whether they steal, for " + std::to_string(device_count) + " devices";
  if (!plan.resting.empty() && int(plan.resting.size()) != device_count)
    return "plan says of " + std::to_string(plan.resting.size()) +
           " devices whether they rest, for " + std::to_string(device_count) + " devices";
  size_t taking_part = 0;
  for (size_t d = 0; d < plan.assigned.size(); ++d) {
    if (!plan.rests(d)) {
      ++taking_part;
      continue;
    }
    if (!plan.assigned[d].empty() || plan.ratios[d] != 0)
      return "device " + std::to_string(d) + " rests but has work";
  }
  if (taking_part == 0 && !plan.all_items().empty()) return "every device rests";
  const Quality& q = plan.quality;
  if (!(q.image_scale > 0 && q.image_scale <= 1))
    return "image scale " + std::to_string(q.image_scale) + " is outside (0, 1]";
  if (!(q.step_scale > 0 && std::isfinite(q.step_scale)))
    return "step scale " + std::to_string(q.step_scale) + " is not a finite number > 0";
  const FrameShape rendered = scaled_shape(shape, q.image_scale);
  return coverage_error(plan.all_items(), rendered.width, rendered.height, rendered.views);
}

}  // namespace multiray::balance
