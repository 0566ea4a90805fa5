#include "balance/hierarchy.h"

#include "util/spec.h"

namespace multiray::balance {

std::string top_level_spec(const std::string& spec) {
  const Spec parsed(spec);
  if (parsed.name() != "semi-static" || parsed.has("split")) return spec;
  return spec + (parsed.has("cut") ? ":split=rows" : ":split=rows:cut=line");
}

CutAxis band_axis(const Rect& part, int frame_width, int frame_height) {
  if (part.empty() || part.x0 < 0 || part.y0 < 0 || part.x1 > frame_width ||
      part.y1 > frame_height)
    return CutAxis::none;
  const bool full_width = part.x0 == 0 && part.x1 == frame_width;
  const bool full_height = part.y0 == 0 && part.y1 == frame_height;
  if (full_width && !full_height) return CutAxis::rows;
  if (full_height && !full_width) return CutAxis::columns;
  return CutAxis::none;
}

bool lower_level_transposed(CutAxis outer, CutAxis inner, bool same_direction) {
  if (outer == CutAxis::none || inner == CutAxis::none) return false;
  const CutAxis across = outer == CutAxis::rows ? CutAxis::columns : CutAxis::rows;
  const CutAxis wanted = same_direction ? outer : across;
  return inner != wanted;
}

}  // namespace multiray::balance
