// Turning fixed ratios into a plan: the geometry shared by uniform, static and dlb.
#pragma once

#include <string>
#include <vector>

#include "balance/balancer.h"
#include "balance/plan.h"

namespace multiray::balance {

enum class Layout {
  Rows,     // one horizontal band per device in every view
  Columns,  // one vertical band per device in every view
  Strips,   // shuffled strips (van Antwerpen et al.) of every view
  Views,    // whole views: device i gets about ratios[i]·views consecutive views.
            // multiray's own mapping: Leria et al. give every device a part of every view
            // and name that full bipartite mapping a limitation (§6.3)
};

// The direction `layout` cuts a view in: rows, columns, or none (strips, whole views).
CutAxis cut_axis_of(Layout layout);

// "rows", "columns", "strips", "views".
std::string to_string(Layout layout);
Layout layout_from_string(const std::string& text);  // throws std::invalid_argument
std::vector<std::string> layout_names();

// Gives device i the share ratios[i] of every view's area in `layout`; everything is in
// `assigned`, nothing shared, no stealing; plan.ratios = `ratios` (the caller normalises).
// `strip_bits` < 0 picks the paper's strip size. Area, not pixel_weight, is split: these
// are the fixed-ratio baselines.
Plan plan_from_ratios(const FrameShape& shape, const std::vector<double>& ratios, Layout layout,
                      int strip_bits = -1);

}  // namespace multiray::balance
