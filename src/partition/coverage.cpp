#include "partition/coverage.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
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

// The first pixel (row-major) of one view that none of `rects` covers, or "" when they
// cover width×height. The rects are in the frame and disjoint (first_overlap() found
// none), so a row is whole exactly when the widths of the rects spanning it add up to
// `width`: a sweep along y over the rects' top and bottom edges finds the first row that
// is not, and that row's spans, sorted, its first gap. O(n log n) in the rects, whatever
// the frame's size (a hostile trace may declare 2^20 x 2^20 pixels).
std::string first_uncovered(const std::vector<Rect>& rects, int width, int height, int view) {
  std::vector<std::pair<int, int64_t>> edges;  // (y, width entering (+) or leaving (-))
  edges.reserve(2 * rects.size());
  for (const Rect& r : rects)
    edges.push_back({r.y0, r.width()}), edges.push_back({r.y1, -r.width()});
  std::sort(edges.begin(), edges.end());
  int64_t spanned = 0;  // width of the rects spanning row y
  size_t k = 0;
  for (int y = 0; y < height;) {
    while (k < edges.size() && edges[k].first <= y) spanned += edges[k++].second;
    if (spanned < width) {
      std::vector<std::pair<int, int>> spans;
      for (const Rect& r : rects)
        if (r.y0 <= y && y < r.y1) spans.push_back({r.x0, r.x1});
      std::sort(spans.begin(), spans.end());
      int x = 0;
      for (const auto& [x0, x1] : spans) {
        if (x0 > x) break;
        x = x1;
      }
      return where(x, y, view);
    }
    y = k < edges.size() ? edges[k].first : height;
  }
  return "";
}

}  // namespace

std::string coverage_error(const std::vector<WorkItem>& items, int width, int height, int views) {
  if (width < 0 || height < 0 || views < 0) return "negative frame size";
  // Only the views that have items, so that the cost follows the items, not the views.
  std::map<int, std::vector<Rect>> per_view;
  for (const WorkItem& item : items) {
    const Rect& r = item.rect;
    const auto name = [&] {
      return "item [" + std::to_string(r.x0) + "," + std::to_string(r.x1) + ")x[" +
             std::to_string(r.y0) + "," + std::to_string(r.y1) + ") of view " +
             std::to_string(item.view);
    };
    // Corners swapped, not an empty share: whatever wrote it is wrong.
    if (r.x1 < r.x0 || r.y1 < r.y0) return name() + " is inverted";
    if (r.empty()) continue;
    if (item.view < 0 || item.view >= views || r.x0 < 0 || r.y0 < 0 || r.x1 > width ||
        r.y1 > height)
      return name() + " is outside the " + std::to_string(width) + "x" + std::to_string(height) +
             "x" + std::to_string(views) + " frame";
    per_view[item.view].push_back(r);
  }
  for (const auto& [v, rects] : per_view)
    if (const std::string twice = first_overlap(rects, v); !twice.empty())
      return "pixel " + twice + " is covered twice";
  // Disjoint rects inside the frame cover it exactly when their areas add up to it.
  if (width == 0 || height == 0) return "";
  for (int v = 0; v < views; ++v) {
    const auto found = per_view.find(v);
    if (found == per_view.end()) return "pixel " + where(0, 0, v) + " is not covered";
    int64_t area = 0;
    for (const Rect& r : found->second) area += r.area();
    if (area != int64_t(width) * int64_t(height))
      return "pixel " + first_uncovered(found->second, width, height, v) + " is not covered";
  }
  return "";
}

}  // namespace multiray::balance
