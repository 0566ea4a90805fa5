// The unit of work every layer speaks: a half-open pixel rectangle of one view, the item
// of work it makes, and a device's report of having rendered one. Header-only and free of
// dependencies, so a renderer can adopt it as is; multiray::balance names the same types
// (balance::Rect, balance::WorkItem, balance::ItemReport).
#pragma once

#include <cstdint>

namespace multiray {

// Pixels [x0, x1) × [y0, y1) of one view. Empty when x1 <= x0 or y1 <= y0.
struct Rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 > x0 ? x1 - x0 : 0; }
  int height() const { return y1 > y0 ? y1 - y0 : 0; }
  // Pixel count (0 for an empty rect); 64-bit because views of 2^31 pixels exist in tests.
  int64_t area() const { return int64_t(width()) * int64_t(height()); }
  bool empty() const { return area() == 0; }
};

inline bool operator==(const Rect& a, const Rect& b) {
  return a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1;
}
inline bool operator!=(const Rect& a, const Rect& b) { return !(a == b); }

// A rect of one view (views are numbered 0..views-1 in the frame's FrameShape).
struct WorkItem {
  Rect rect;
  int view = 0;
};

inline bool operator==(const WorkItem& a, const WorkItem& b) {
  return a.view == b.view && a.rect == b.rect;
}
inline bool operator!=(const WorkItem& a, const WorkItem& b) { return !(a == b); }

// One item as a device rendered it, measured inside the device: `time_ms` is the whole
// item cost the device (rendering + emulated idle + per-item overhead), `busy_ms` the
// rendering alone (0 where unknown); `samples` the samples it took (0 if not counted);
// `id` its number in the frame's Dispatcher (Plan::all_items() order). A device rendering
// several items at once charges each its share of the time (a CPU device's threads: the
// time is split evenly among the items in progress), so a frame's item times add up to
// the device's time either way.
struct ItemReport {
  WorkItem item;
  double time_ms = 0;
  double samples = 0;
  double busy_ms = 0;
  uint32_t id = 0;
};

}  // namespace multiray
