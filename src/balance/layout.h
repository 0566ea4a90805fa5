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

// How many shuffled strips a view is cut into, one rule for every balancer that lays out
// strips (uniform, static, dlb), so that a baseline cuts exactly dlb's strips: 2^bits per
// view, or with bits < 0 the most strips of at least `min_strip` pixels each and at most
// `max_items` strips over all of the frame's views (why: dlb.h).
struct StripRule {
  int bits = -1;          // log2 strips per view, 0..24, or < 0: automatic
  int min_strip = 32;     // least pixels per strip when automatic, 1..65536
  int max_items = 16384;  // most strips per frame when automatic, >= 1
};
int strip_bits(const FrameShape& shape, const StripRule& rule);
// "bits=auto:strip=32:items=16384", as the registry's parameters spell it.
std::string to_spec(const StripRule& rule);

// Gives device i the share ratios[i] of every view's area in `layout`; everything is in
// `assigned`, nothing shared, no stealing; plan.ratios = `ratios` (the caller normalises).
// Strips are cut by `strips`. Area, not pixel_weight, is split: these are the fixed-ratio
// baselines.
Plan plan_from_ratios(const FrameShape& shape, const std::vector<double>& ratios, Layout layout,
                      const StripRule& strips = {});

}  // namespace multiray::balance
