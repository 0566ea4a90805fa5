#include "partition/coverage.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
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

// A pixel of `view` covered by two of `rects` (in the frame, non-empty), or "" when none
// overlap: a sweep along x over the rects' left and right edges, keeping the y-intervals
// of the rects that span the sweep position, which are disjoint while nothing overlaps,
// so a new interval need only be compared with its neighbours. O(n log n) in the rects.
std::string first_overlap(const std::vector<Rect>& rects, int view) {
  struct Edge {
    int x;
    bool opens;
    size_t rect;
  };
  std::vector<Edge> edges;
  edges.reserve(2 * rects.size());
  for (size_t i = 0; i < rects.size(); ++i)
    edges.push_back({rects[i].x0, true, i}), edges.push_back({rects[i].x1, false, i});
  // Half-open rects: at one x, those ending there leave before those starting there enter.
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.x != b.x ? a.x < b.x : (!a.opens && b.opens);
  });
  std::map<int, int> open;  // y0 -> y1 of the rects spanning the sweep position
  for (const Edge& e : edges) {
    const Rect& r = rects[e.rect];
    if (!e.opens) {
      open.erase(r.y0);
      continue;
    }
    const auto next = open.lower_bound(r.y0);
    if (next != open.end() && next->first < r.y1) return where(e.x, next->first, view);
    if (next != open.begin() && std::prev(next)->second > r.y0) return where(e.x, r.y0, view);
    open.emplace(r.y0, r.y1);
  }
  return "";
}

// The first pixel (row-major, view by view) no item covers, by painting them: only on the
// error path, to name the pixel.
std::string first_uncovered(const std::vector<std::vector<Rect>>& per_view, int width,
                            int height) {
  const size_t per = size_t(width) * size_t(height);
  std::vector<uint8_t> hit(per);
  for (size_t v = 0; v < per_view.size(); ++v) {
    std::fill(hit.begin(), hit.end(), uint8_t(0));
    for (const Rect& r : per_view[v])
      for (int y = r.y0; y < r.y1; ++y)
        std::fill_n(hit.begin() + std::ptrdiff_t(size_t(y) * size_t(width) + size_t(r.x0)),
                    r.x1 - r.x0, uint8_t(1));
    for (size_t p = 0; p < per; ++p)
      if (!hit[p]) return where(int(p % size_t(width)), int(p / size_t(width)), int(v));
  }
  return "";
}

}  // namespace

std::string coverage_error(const std::vector<WorkItem>& items, int width, int height, int views) {
  if (width < 0 || height < 0 || views < 0) return "negative frame size";
  std::vector<std::vector<Rect>> per_view(static_cast<size_t>(views));
  for (const WorkItem& item : items) {
    const Rect& r = item.rect;
    if (r.empty()) continue;
    if (item.view < 0 || item.view >= views || r.x0 < 0 || r.y0 < 0 || r.x1 > width ||
        r.y1 > height)
      return "item [" + std::to_string(r.x0) + "," + std::to_string(r.x1) + ")x[" +
             std::to_string(r.y0) + "," + std::to_string(r.y1) + ") of view " +
             std::to_string(item.view) + " is outside the " + std::to_string(width) + "x" +
             std::to_string(height) + "x" + std::to_string(views) + " frame";
    per_view[size_t(item.view)].push_back(r);
  }
  // Disjoint rects inside the frame cover it exactly when their areas add up to it.
  bool short_of_pixels = false;
  for (size_t v = 0; v < per_view.size(); ++v) {
    if (const std::string twice = first_overlap(per_view[v], int(v)); !twice.empty())
      return "pixel " + twice + " is covered twice";
    int64_t area = 0;
    for (const Rect& r : per_view[v]) area += r.area();
    short_of_pixels |= area != int64_t(width) * int64_t(height);
  }
  if (short_of_pixels)
    return "pixel " + first_uncovered(per_view, width, height) + " is not covered";
  return "";
}

}  // namespace multiray::balance
