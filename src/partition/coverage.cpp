#include "partition/coverage.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace multiray::balance {

namespace {
std::string where(int x, int y, int view) {
  // Appends rather than "(" + ...: GCC 12 warns falsely (-Wrestrict) on the latter.
  std::string s = "(";
  s += std::to_string(x);
  s += ',';
  s += std::to_string(y);
  s += ") of view ";
  s += std::to_string(view);
  return s;
}
}  // namespace

std::string coverage_error(const std::vector<WorkItem>& items, int width, int height, int views) {
  if (width < 0 || height < 0 || views < 0) return "negative frame size";
  const size_t per_view = size_t(width) * size_t(height);
  std::vector<uint8_t> hits(per_view * size_t(views), 0);
  for (const WorkItem& item : items) {
    const Rect& r = item.rect;
    if (r.empty()) continue;
    if (item.view < 0 || item.view >= views || r.x0 < 0 || r.y0 < 0 || r.x1 > width ||
        r.y1 > height)
      return "item [" + std::to_string(r.x0) + "," + std::to_string(r.x1) + ")x[" +
             std::to_string(r.y0) + "," + std::to_string(r.y1) + ") of view " +
             std::to_string(item.view) + " is outside the " + std::to_string(width) + "x" +
             std::to_string(height) + "x" + std::to_string(views) + " frame";
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        uint8_t& h = hits[size_t(item.view) * per_view + size_t(y) * size_t(width) + size_t(x)];
        if (h) return "pixel " + where(x, y, item.view) + " is covered twice";
        h = 1;
      }
  }
  for (size_t i = 0; i < hits.size(); ++i)
    if (!hits[i]) {
      const size_t v = i / per_view, p = i % per_view;
      return "pixel " + where(int(p % size_t(width)), int(p / size_t(width)), int(v)) +
             " is not covered";
    }
  return "";
}

}  // namespace multiray::balance
