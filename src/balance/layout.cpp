#include "balance/layout.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

#include "partition/apportion.h"
#include "partition/bands.h"
#include "partition/shuffled_strips.h"

namespace multiray::balance {

std::string to_string(Layout layout) {
  switch (layout) {
    case Layout::Rows:
      return "rows";
    case Layout::Columns:
      return "columns";
    case Layout::Strips:
      return "strips";
    case Layout::Views:
      return "views";
  }
  return "rows";
}

CutAxis cut_axis_of(Layout layout) {
  if (layout == Layout::Rows) return CutAxis::rows;
  if (layout == Layout::Columns) return CutAxis::columns;
  return CutAxis::none;
}

std::vector<std::string> layout_names() { return {"rows", "columns", "strips", "views"}; }

Layout layout_from_string(const std::string& text) {
  for (Layout l : {Layout::Rows, Layout::Columns, Layout::Strips, Layout::Views})
    if (to_string(l) == text) return l;
  throw std::invalid_argument("unknown layout '" + text +
                              "' (known: rows, columns, strips, views)");
}

int strip_bits(const FrameShape& shape, const StripRule& rule) {
  if (rule.bits >= 0) return rule.bits;
  int bits = strip_bits_for(shape.pixels_per_view(), rule.min_strip);
  const int64_t per_view =
      std::max<int64_t>(1, int64_t(rule.max_items) / std::max(1, shape.views));
  while (bits > 0 && (int64_t(1) << bits) > per_view) --bits;
  return bits;
}

std::string to_spec(const StripRule& rule) {
  return "bits=" + (rule.bits < 0 ? std::string("auto") : std::to_string(rule.bits)) +
         ":strip=" + std::to_string(rule.min_strip) + ":items=" + std::to_string(rule.max_items);
}

Plan plan_from_ratios(const FrameShape& shape, const std::vector<double>& ratios, Layout layout,
                      const StripRule& strips) {
  Plan plan;
  plan.ratios = ratios;
  plan.assigned.resize(ratios.size());
  if (shape.pixels() == 0) return plan;
  if (layout == Layout::Views) {
    const std::vector<int64_t> counts = apportion(ratios, shape.views);
    int view = 0;
    for (size_t i = 0; i < counts.size(); ++i)
      for (int64_t k = 0; k < counts[i]; ++k, ++view)
        plan.assigned[i].push_back(WorkItem{Rect{0, 0, shape.width, shape.height}, view});
    return plan;
  }
  if (layout == Layout::Strips) {
    plan.assigned =
        shuffled_strips(shape.width, shape.height, shape.views, ratios, strip_bits(shape, strips));
    return plan;
  }
  const std::vector<Rect> bands = split_bands(shape.width, shape.height, ratios,
                                              layout == Layout::Rows ? Axis::Rows : Axis::Columns);
  for (int view = 0; view < shape.views; ++view)
    for (size_t i = 0; i < bands.size(); ++i)
      if (!bands[i].empty()) plan.assigned[i].push_back(WorkItem{bands[i], view});
  return plan;
}

}  // namespace multiray::balance
