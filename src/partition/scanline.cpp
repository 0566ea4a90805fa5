#include "partition/scanline.h"

#include <algorithm>

namespace multiray::balance {

void append_scanline_rects(int width, int64_t begin, int64_t end, int view,
                           std::vector<WorkItem>& out) {
  if (width <= 0 || end <= begin) return;
  int64_t y = begin / width;
  int64_t x = begin % width;
  if (x != 0) {  // partial first row
    const int64_t x_end = std::min<int64_t>(width, x + (end - begin));
    out.push_back(WorkItem{Rect{int(x), int(y), int(x_end), int(y + 1)}, view});
    begin += x_end - x;
    ++y;
  }
  const int64_t whole_rows = (end - begin) / width;
  if (whole_rows > 0) {
    out.push_back(WorkItem{Rect{0, int(y), width, int(y + whole_rows)}, view});
    begin += whole_rows * width;
    y += whole_rows;
  }
  if (end > begin)  // partial last row
    out.push_back(WorkItem{Rect{0, int(y), int(end - begin), int(y + 1)}, view});
}

void append_flat_range(int width, int height, int64_t begin, int64_t end,
                       std::vector<WorkItem>& out) {
  const int64_t per_view = int64_t(width) * height;
  if (per_view <= 0) return;
  while (begin < end) {
    const int64_t view = begin / per_view;
    const int64_t view_end = std::min(end, (view + 1) * per_view);
    append_scanline_rects(width, begin - view * per_view, view_end - view * per_view, int(view),
                          out);
    begin = view_end;
  }
}

void append_flat_column_range(int width, int height, int64_t begin, int64_t end,
                              std::vector<WorkItem>& out) {
  // Column order is scanline order of the transposed image: cut there, transpose back.
  std::vector<WorkItem> transposed;
  append_flat_range(height, width, begin, end, transposed);
  for (const WorkItem& t : transposed)
    out.push_back(WorkItem{Rect{t.rect.y0, t.rect.x0, t.rect.y1, t.rect.x1}, t.view});
}

}  // namespace multiray::balance
